"""Windows: their bounds, their keys, and the motion a window needs."""

from __future__ import annotations

import pytest
from axisflow.fleet.catalog import CatalogEntry
from axisflow.fleet.errors import FleetValueError
from axisflow.fleet.windows import NS_PER_DAY, MotionRule, WindowSpec, plan_windows

DAY0 = 1_767_571_200_000_000_000  # 2026-01-05T00:00:00Z


def _entry(path: str, start_ns: int, seconds: float, axis: str = "a0", digest: str = "h1", ok: bool = True):
    return CatalogEntry(
        path=path,
        axis=axis,
        topic=f"/axisflow/{axis}/state",
        joint="motor",
        joint_kind="motor",
        size_bytes=1,
        mtime_ns=1,
        content_hash=digest,
        start_ns=start_ns,
        end_ns=start_ns + int(seconds * 1e9),
        samples=int(seconds * 1000),
        holes=0,
        missing=0,
        speed_low_m_s=0.01,
        speed_high_m_s=0.5,
        reversals=20,
        moving_s=0.8 * seconds,
        status="ok" if ok else "unreadable",
        reason="",
    )


def test_day_windows_group_an_axis_s_logs_by_utc_day():
    entries = [
        _entry("/a", DAY0 + 8 * 3600 * 10**9, 30),
        _entry("/b", DAY0 + 14 * 3600 * 10**9, 30, digest="h2"),
        _entry("/c", DAY0 + NS_PER_DAY + 8 * 3600 * 10**9, 30, digest="h3"),
        _entry("/d", DAY0, 30, axis="a1"),
        _entry("/e", DAY0, 30, ok=False),
    ]
    windows = plan_windows(entries, WindowSpec.parse("day"), "m")
    assert [(w.axis, w.start_ns, len(w.parts)) for w in windows] == [
        ("a0", DAY0, 2),
        ("a0", DAY0 + NS_PER_DAY, 1),
        ("a1", DAY0, 1),
    ]
    assert windows[0].moving_s == pytest.approx(48.0) and windows[0].end_ns == DAY0 + NS_PER_DAY


def test_a_log_across_a_boundary_belongs_to_both_windows_with_its_share_of_motion():
    entries = [_entry("/a", DAY0 + 50 * 10**9, 20)]  # 50 s to 70 s after midnight
    windows = plan_windows(entries, WindowSpec.parse("60"), "m")
    assert [(w.start_ns - DAY0) // 10**9 for w in windows] == [0, 60]
    assert [w.moving_s for w in windows] == pytest.approx([8.0, 8.0])


def test_sessions_are_the_logs():
    entries = [_entry("/a", DAY0, 30), _entry("/b", DAY0 + 100 * 10**9, 30, digest="h2")]
    assert len(plan_windows(entries, WindowSpec.parse("session"), "m")) == 2


def test_a_key_changes_with_the_content_and_the_method_only():
    a = plan_windows([_entry("/a", DAY0, 30)], WindowSpec.parse("day"), "m")[0]
    moved = plan_windows([_entry("/elsewhere/a", DAY0, 30)], WindowSpec.parse("day"), "m")[0]
    changed = plan_windows([_entry("/a", DAY0, 30, digest="h9")], WindowSpec.parse("day"), "m")[0]
    other = plan_windows([_entry("/a", DAY0, 30)], WindowSpec.parse("day"), "m2")[0]
    assert a.key == moved.key and len({a.key, changed.key, other.key}) == 3


@pytest.mark.parametrize("text", ["week", "5", "nan", "-60"])
def test_a_bad_window_is_refused_naming_it(text):
    with pytest.raises(FleetValueError, match=f"--window '?{text}"):
        WindowSpec.parse(text)


def test_the_motion_rule_names_what_is_short():
    rule = MotionRule()
    assert rule.shortfall(20.0, 30, 0.5) == ""
    why = rule.shortfall(0.0, 0, 0.0)
    assert "moving 0.0 s < 5 s" in why and "0 reversals < 4" in why and "top speed 0 m/s < 0.05 m/s" in why
