"""A private network namespace for DDS runs that must not reach beyond this machine (the tests and
``axisflow bench ros2``): ``unshare -n`` gives a process a network of its own with only a loopback
interface; it is brought up with multicast routed to it, so DDS discovery works inside and nothing
leaves. Needs root (or an unprivileged user namespace) and util-linux's ``unshare`` with iproute2's
``ip``; :func:`unavailable` says why not where they are missing.
"""

from __future__ import annotations

import os
import shutil
import subprocess

INSIDE_ENV = "AXISFLOW_IN_PRIVATE_NETNS"
"""set (to 1) in the environment of what runs inside the namespace"""
SETUP = "ip link set lo up && ip link set lo multicast on && ip route add 224.0.0.0/4 dev lo"
"""the namespace's loopback, up, with multicast routed to it"""


def inside() -> bool:
    """Whether this process was started inside a namespace by :func:`command`."""
    return os.environ.get(INSIDE_ENV) == "1"


def unavailable() -> str | None:
    """Why no private network namespace can be made here, or None if one can (tried once)."""
    if shutil.which("unshare") is None or shutil.which("ip") is None:
        return "unshare or ip (util-linux, iproute2) is not installed"
    probe = subprocess.run(["unshare", "-n", "sh", "-c", SETUP], capture_output=True, text=True, check=False)
    if probe.returncode != 0:
        return f"`unshare -n` failed: {probe.stderr.strip() or f'exit code {probe.returncode}'}"
    return None


def command(argv: list[str]) -> list[str]:
    """``argv`` run inside a fresh private network namespace (run it with :data:`INSIDE_ENV` = 1)."""
    return ["unshare", "-n", "sh", "-c", f'{SETUP} && exec "$@"', "sh", *argv]


def interfaces() -> list[str]:
    """The network interfaces this process sees (inside the namespace: only ``lo``)."""
    out = subprocess.run(["ip", "-o", "link"], capture_output=True, text=True, check=True).stdout
    return [line.split(":")[1].strip().split("@")[0] for line in out.splitlines() if line.strip()]
