"""Input and output checks, and atomic writes: files compared by device and inode (links too), refusals
that name the path and the reason, and writers that leave the old file or the whole new one — never a
part, never a temporary file."""

from __future__ import annotations

import os
import signal

import pytest
from axisflow.model.files import (
    InputError,
    OutputError,
    atomic_path,
    check_distinct_inputs,
    check_input_file,
    check_output_file,
    read_json,
    signals_held,
    write_atomic,
    write_atomic_files,
)

LONG = "x" * 300


@pytest.fixture
def folder(tmp_path):
    (tmp_path / "log.mcap").write_bytes(b"recording")
    (tmp_path / "soft.mcap").symlink_to("log.mcap")
    os.link(tmp_path / "log.mcap", tmp_path / "hard.mcap")
    (tmp_path / "dir").mkdir()
    return tmp_path


INPUT_CASES = [
    ("missing.mcap", r"log .*missing\.mcap does not exist"),
    ("dir", r"log .*dir is a directory, not a file"),
    (LONG, rf"log .*{LONG} cannot be read: File name too long"),
    ("log.mcap/x", r"cannot be read: Not a directory"),
]


@pytest.mark.parametrize(("name", "match"), INPUT_CASES, ids=[c[1][:30] for c in INPUT_CASES])
def test_an_input_that_cannot_be_read_is_named_with_the_reason(folder, name, match):
    with pytest.raises(InputError, match=match):
        check_input_file(folder / name, "log")


class _RecordError(Exception):
    pass


def test_a_json_result_file_is_read_back_or_refused_in_one_line_naming_it(tmp_path):
    good = tmp_path / "r.json"
    good.write_text('{"rows": [1, 2.5]}', encoding="utf-8")
    assert read_json(good, _RecordError) == {"rows": [1, 2.5]}
    (tmp_path / "bad.json").write_text("{rows", encoding="utf-8")
    (tmp_path / "latin.json").write_bytes(b'"\xe9"')  # not UTF-8
    for name, match in [
        ("none.json", r"none\.json does not exist"),
        ("bad.json", r"bad\.json cannot be read as JSON: Expecting property name"),
        ("latin.json", r"latin\.json cannot be read as JSON: 'utf-8' codec"),
        (".", r"cannot be read as JSON: \[Errno 21\]"),
    ]:
        with pytest.raises(_RecordError, match=match):
            read_json(tmp_path / name, _RecordError)


def test_one_file_named_twice_is_refused_whatever_its_names(folder):
    check_distinct_inputs([folder / "log.mcap", folder / "missing.mcap"])
    for other in ("log.mcap", "soft.mcap", "hard.mcap"):
        with pytest.raises(InputError, match=rf"log .*log\.mcap and log .*{other} are the same file"):
            check_distinct_inputs([folder / "log.mcap", folder / other], "log")


OUTPUT_CASES = [
    ("log.mcap", {}, r"is the input .*log\.mcap: an output must never write over an input"),
    ("soft.mcap", {"overwrite": True}, r"is the input .*log\.mcap under another name \(a link\)"),
    ("hard.mcap", {"overwrite": True}, r"is the input .*log\.mcap under another name \(a link\)"),
    ("new.mcap", {"suffix": ".rrd"}, r"output .*new\.mcap must end in \.rrd"),
    ("dir", {"overwrite": True}, r"output .*dir is a directory, not a file"),
    ("nowhere/x.mcap", {}, r"output .*x\.mcap: folder .*nowhere does not exist"),
    (f"{LONG}.mcap", {}, r"cannot be written: File name too long"),
    ("other.mcap", {}, r"output .*other\.mcap already exists: choose another name or pass --overwrite"),
]


@pytest.mark.parametrize(("name", "kw", "match"), OUTPUT_CASES, ids=[c[2][:30] for c in OUTPUT_CASES])
def test_an_output_that_must_not_be_written_is_refused_before_anything(folder, name, kw, match):
    (folder / "other.mcap").write_bytes(b"an earlier result")
    before = sorted(os.listdir(folder))
    with pytest.raises(OutputError, match=match):
        check_output_file(folder / name, inputs=[folder / "log.mcap"], **kw)
    assert sorted(os.listdir(folder)) == before
    assert (folder / "log.mcap").read_bytes() == b"recording"


def test_an_existing_output_is_replaced_with_overwrite_and_a_link_never_written_through(folder):
    (folder / "link.txt").symlink_to("log.mcap")
    assert check_output_file(folder / "new.txt") == folder / "new.txt"
    check_output_file(folder / "link.txt", overwrite=True)  # a link to something that is no input
    write_atomic(folder / "link.txt", "result\n")
    assert not (folder / "link.txt").is_symlink() and (folder / "link.txt").read_text() == "result\n"
    assert (folder / "log.mcap").read_bytes() == b"recording"  # the link was replaced, not followed


def test_a_failed_write_leaves_the_old_file_and_no_temporary_file(tmp_path):
    target = tmp_path / "result.txt"
    target.write_text("old")
    with pytest.raises(RuntimeError), atomic_path(target) as part:
        part.write_text("half of the new")
        assert part.parent == tmp_path and part.name.startswith(".result.txt.") and part.suffix == ".part"
        raise RuntimeError("the writer failed")
    assert os.listdir(tmp_path) == ["result.txt"] and target.read_text() == "old"


def test_a_target_whose_name_is_near_the_limit_still_gets_a_temporary_file_beside_it(tmp_path):
    target = tmp_path / ("y" * 250)
    write_atomic(target, b"data")
    assert os.listdir(tmp_path) == [target.name] and target.read_bytes() == b"data"


def test_files_that_land_together_land_all_or_none(tmp_path):
    (tmp_path / "a.txt").write_text("old a")
    with pytest.raises(OutputError, match="cannot write into"):
        write_atomic_files(tmp_path, {"a.txt": "new a", "sub/b.txt": "new b"})  # b's folder is missing
    assert os.listdir(tmp_path) == ["a.txt"] and (tmp_path / "a.txt").read_text() == "old a"
    written = write_atomic_files(tmp_path, {"a.txt": "new a", "b.txt": b"new b"})
    assert written == [tmp_path / "a.txt", tmp_path / "b.txt"]
    assert sorted(os.listdir(tmp_path)) == ["a.txt", "b.txt"]
    assert (tmp_path / "a.txt").read_text() == "new a" and (tmp_path / "b.txt").read_bytes() == b"new b"
    assert oct((tmp_path / "b.txt").stat().st_mode & 0o777) == oct(0o666 & ~_umask())


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def test_a_signal_while_files_land_acts_after_the_last_one():
    heard: list[str] = []

    def handler(_signum: int, _frame: object) -> None:
        heard.append("handled")

    previous = signal.signal(signal.SIGHUP, handler)
    try:
        with signals_held():
            signal.raise_signal(signal.SIGHUP)
            heard.append("inside")  # the handler has not run yet
        heard.append("after")
    finally:
        signal.signal(signal.SIGHUP, previous)
    assert heard == ["inside", "handled", "after"]
