"""``axisflow fleet index`` through the command line: an unreadable log among good ones is one
warning line and exit 0; when no log can be read, one error line and exit 2."""

from __future__ import annotations

from axisflow.acquisition.logs.synthetic_log import SyntheticLogSpec, write_synthetic_log

from axisflow.cli import main


def test_an_unreadable_log_among_good_ones_is_one_line_and_the_rest_indexed(tmp_path, capfd):
    (tmp_path / "logs").mkdir()
    write_synthetic_log(tmp_path / "logs" / "good.mcap", SyntheticLogSpec(duration_s=2.0))
    (tmp_path / "logs" / "bad.mcap").write_bytes(b"garbage")
    assert main(["fleet", "index", str(tmp_path / "logs"), "--catalog", str(tmp_path / "cat")]) == 0
    out, err = capfd.readouterr()
    lines = err.strip().splitlines()
    warned = [line for line in lines if ": warning: " in line]
    assert len(warned) == 1 and "bad.mcap: cannot be indexed" in warned[0] and "not an MCAP file" in warned[0]
    assert "2 rows (1 axes)" in out and "1 unreadable" in out


def test_nothing_readable_is_exit_2(tmp_path, capfd):
    (tmp_path / "logs").mkdir()
    (tmp_path / "logs" / "bad.mcap").write_bytes(b"garbage")
    assert main(["fleet", "index", str(tmp_path / "logs"), "--catalog", str(tmp_path / "cat")]) == 2
    err = capfd.readouterr().err.strip().splitlines()
    assert err[-1] == "axisflow fleet: error: none of the 1 logs could be indexed (each is named above)"
    assert sum("warning" in line for line in err) == 1
