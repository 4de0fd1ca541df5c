"""Keys of the wire contract: a key inside any key expression, checked by Zenoh's own matching."""

import pytest
import zenoh
from axisflow.acquisition.wire.keys import KeyExprError, key_within


@pytest.mark.parametrize(
    "expression",
    ["axisflow/**", "axisflow/*/state", "**", "axisflow/a$*/state", "a/**/b/*", "axisflow/a0/state", "@x/**"],
)
def test_the_key_lies_within_the_expression_and_has_no_wildcard(expression):
    key = key_within(expression, "_wake_42")
    assert zenoh.KeyExpr(expression).includes(zenoh.KeyExpr(key))
    assert "*" not in key and "$" not in key


@pytest.mark.parametrize("chunk", ["@wake", "a/b", "a*", ""])
def test_a_filler_no_wildcard_would_match_is_refused(chunk):
    with pytest.raises(KeyExprError, match="filler chunk"):
        key_within("axisflow/**", chunk)
