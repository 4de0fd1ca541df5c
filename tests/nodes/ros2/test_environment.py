"""The ROS 2 variables, read and checked before any ROS 2 call."""

from __future__ import annotations

import pytest

from axisflow.nodes.ros2.environment import RosEnvironment
from axisflow.nodes.ros2.errors import Ros2Error


def test_the_defaults_are_domain_0_and_the_subnet():
    env = RosEnvironment.from_environ({})
    assert (env.domain_id, env.discovery_range, env.rmw) == (0, "SUBNET", "rmw_fastrtps_cpp")
    assert not env.on_this_host and "LOCALHOST keeps it here" in env.describe()


@pytest.mark.parametrize(
    ("environ", "here"),
    [
        ({"ROS_DOMAIN_ID": "17", "ROS_AUTOMATIC_DISCOVERY_RANGE": "localhost"}, True),
        ({"ROS_AUTOMATIC_DISCOVERY_RANGE": "OFF"}, True),
        ({"ROS_AUTOMATIC_DISCOVERY_RANGE": "OFF", "ROS_STATIC_PEERS": "192.168.1.7"}, False),
        ({"ROS_AUTOMATIC_DISCOVERY_RANGE": "SYSTEM_DEFAULT"}, False),
    ],
)
def test_on_this_host(environ, here):
    assert RosEnvironment.from_environ(environ).on_this_host is here


@pytest.mark.parametrize(
    ("environ", "says"),
    [
        ({"ROS_DOMAIN_ID": "233"}, "ROS_DOMAIN_ID = '233' is not a domain id (an integer 0…232)"),
        ({"ROS_DOMAIN_ID": "-1"}, "ROS_DOMAIN_ID = '-1'"),
        ({"ROS_DOMAIN_ID": "x"}, "ROS_DOMAIN_ID = 'x'"),
        ({"ROS_AUTOMATIC_DISCOVERY_RANGE": "WORLD"}, "ROS_AUTOMATIC_DISCOVERY_RANGE = 'WORLD' is not one of"),
    ],
)
def test_a_bad_variable_is_named(environ, says):
    with pytest.raises(Ros2Error) as bad:
        RosEnvironment.from_environ(environ)
    assert says in str(bad.value)
