"""Command-line behaviour: commands exit (no hang), user errors exit 2 without a traceback."""

import pytest


def test_record_and_bridge_exit_on_their_own(cli, tmp_path, port):
    rec = cli.start(
        "record", "-o", str(tmp_path / "x.mcap"), "--listen", f"tcp/127.0.0.1:{port}", "--duration", "1"
    )
    bridge = cli.run(
        "bridge", "--sim", "--connect", f"tcp/127.0.0.1:{port}", "--duration", "0.5", "--speed", "0"
    )
    assert bridge.returncode == 0, bridge.stderr
    out, err = cli.finish(rec, timeout=30)  # fails the test if the recorder hangs at exit
    assert "recorded" in out, err


def test_bridge_with_default_zenoh_config_exits_even_when_7447_is_taken(cli):
    """The embedded default listens on 7447 if free and on a port of its own: it must also work when
    something else (here: a plain socket, or whatever already holds it) has 7447, so the test does
    not depend on the port being free."""
    import socket

    holder = socket.socket()
    try:
        holder.bind(("127.0.0.1", 7447))
        holder.listen()
    except OSError:
        pass  # already taken by another process: the same situation
    try:
        result = cli.run("bridge", "--sim", "--duration", "0.2", "--speed", "0", "--json", timeout=60)
    finally:
        holder.close()
    assert result.returncode == 0, result.stderr
    assert '"ticks": 200' in result.stdout


@pytest.mark.parametrize(
    ("args", "match"),
    [
        (["bridge", "--sim", "--plant", "missing.toml"], "plant file missing.toml does not exist"),
        (["bridge", "--sim", "--speed", "-1"], "speed = -1.0 must be >= 0"),
        (["bridge", "--sim", "--axis", "a/b"], "axis name 'a/b' is not a valid key-expression part"),
        (["record", "-o", "x.txt"], "must end in .mcap"),
        (["record", "-o", "x.mcap", "--duration", "0"], "duration = 0.0 s must be > 0 s"),
        (["record", "-o", "x.mcap", "--keys", "a//b"], "--keys 'a//b' is not a valid Zenoh key expression"),
        (["bridge", "--sim", "--jump-tolerance", "-1"], "jump tolerance = -1.0 m must be >= 0 m"),
        (["recover", "missing.mcap"], "recording missing.mcap does not exist"),
        (["replay", "missing.mcap"], "recording missing.mcap does not exist"),
        (
            ["bridge", "--sim", "--zenoh-config", "missing.json5"],
            "zenoh config file missing.json5 does not exist",
        ),
    ],
)
def test_user_errors_exit_2_with_a_message(cli, tmp_path, args, match):
    result = cli.run(*args, timeout=30)
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert match in result.stderr
    assert "Traceback" not in result.stderr


def test_pipeline_benchmark_smoke(cli):
    import json

    result = cli.run(
        "bench", "pipeline", "--json", "--axes", "2", "--seconds", "0.5", "--flood", "4000",
        "--memory-seconds", "1", "--memory-axes", "2", timeout=120,
    )  # fmt: skip
    assert result.returncode == 0, result.stderr
    r = json.loads(result.stdout)
    assert r["steps"][0]["axes"] == 2 and r["steps"][0]["lost"] == 0
    assert r["max_axes_zero_loss"] == 2
    assert r["recorder_flood"]["lost"] == 0 and r["recorder_flood"]["ratio_to_baseline"] > 0
    assert r["memory"]["axes"] == 2 and r["memory"]["peak_rss_mb"] > 0


@pytest.mark.parametrize("command", ["recover", "replay"])
@pytest.mark.parametrize("content", [b"abc", bytes(range(256)) * 16], ids=["3-bytes", "4-KiB-noise"])
def test_a_file_that_is_not_mcap_is_refused_and_nothing_is_written(cli, tmp_path, command, content):
    source = tmp_path / "noise.mcap"
    source.write_bytes(content)
    result = cli.run(command, str(source), timeout=30)
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert f"{source} is not an MCAP file" in result.stderr
    assert "Traceback" not in result.stderr
    assert sorted(p.name for p in tmp_path.iterdir()) == ["noise.mcap"]


@pytest.mark.parametrize(
    ("existing", "split_args"),
    [("x.mcap", []), ("x_0000.mcap", ["--split-duration", "1"])],
    ids=["single", "split"],
)
def test_record_refuses_to_overwrite_unless_asked(cli, tmp_path, port, existing, split_args):
    old = tmp_path / existing
    old.write_bytes(b"precious")
    out = str(tmp_path / "x.mcap")
    listen = ["--listen", f"tcp/127.0.0.1:{port}"]
    result = cli.run("record", "-o", out, *split_args, *listen, "--duration", "0.2", timeout=30)
    assert result.returncode == 2, (result.stdout, result.stderr)
    assert f"output {old} already exists" in result.stderr and "--overwrite" in result.stderr
    assert "Traceback" not in result.stderr
    assert old.read_bytes() == b"precious"
    result = cli.run(
        "record", "-o", out, *split_args, *listen, "--duration", "0.2", "--overwrite", timeout=30
    )
    assert result.returncode == 0, result.stderr
    assert old.read_bytes() != b"precious"
