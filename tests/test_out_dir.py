"""``simgrasp evaluate --out DIR``: checked before any work and held by one run at
a time, with real processes: a running sweep, a second one, a SIGKILL."""

from __future__ import annotations

import contextlib
import os
import signal
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest

from simgrasp.runs.out_dir import LOCK_FILE, claim_out_dir

TIMEOUT_S = 120
SWEEP = ["evaluate", "--objects", "gen_hammer", "--detector", "centroid", "--seeds", "200"]


def simgrasp(*args: str, timeout: float = TIMEOUT_S) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "simgrasp", *args],
        capture_output=True,
        text=True,
        timeout=timeout,
        check=False,
    )


def test_a_file_as_out_is_refused_before_any_trial(tmp_path: Path) -> None:
    out = tmp_path / "out"
    out.write_text("not a directory")
    start = time.monotonic()
    done = simgrasp(*SWEEP, "--workers", "2", "--out", str(out))
    assert done.returncode == 2, done.stderr
    assert f"--out {out}: is a file, not a directory" in done.stderr
    assert "Traceback" not in done.stderr
    assert time.monotonic() - start < 30  # the 200 trials were never started
    assert out.read_text() == "not a directory"


def test_a_read_only_out_is_refused_before_any_trial(tmp_path: Path) -> None:
    """A directory without write permission; root ignores permission bits, so as root one
    that is read-only to everyone: /proc/self."""
    out = tmp_path / "out"
    if os.geteuid() == 0:
        out = Path("/proc/self")
    else:
        out.mkdir()
        out.chmod(0o555)
    try:
        done = simgrasp(*SWEEP, "--out", str(out))
    finally:
        if out.parent == tmp_path:
            out.chmod(0o755)
    assert done.returncode == 2 and "not writable" in done.stderr, done.stderr
    assert "Traceback" not in done.stderr
    assert not (out / "trials.jsonl").exists()


def test_an_unwritable_out_is_refused_by_the_write_probe(tmp_path: Path) -> None:
    """Root ignores permission bits, so the probe is exercised with a directory whose log
    cannot be opened for appending: ``trials.jsonl`` is itself a directory."""
    out = tmp_path / "out"
    (out / "trials.jsonl").mkdir(parents=True)
    with (
        pytest.raises(ValueError, match=r"--out .*trials\.jsonl.*not writable"),
        claim_out_dir(out, ["evaluate"]),
    ):
        pass


def test_a_second_run_on_the_same_out_refuses_at_once_naming_the_first(tmp_path: Path) -> None:
    out = tmp_path / "out"
    first = subprocess.Popen(
        [sys.executable, "-m", "simgrasp", *SWEEP, "--workers", "1", "--out", str(out),
         "--no-progress"],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.PIPE,
        start_new_session=True,
    )  # fmt: skip
    try:
        assert first.stderr is not None
        deadline = time.monotonic() + TIMEOUT_S
        while not (out / LOCK_FILE).exists() or str(first.pid) not in (out / LOCK_FILE).read_text():
            assert first.poll() is None, first.stderr.read().decode()[-2000:]
            assert time.monotonic() < deadline, "the first sweep never took its lock"
            time.sleep(0.05)
        second = simgrasp(*SWEEP, "--out", str(out), timeout=60)
        # at once: the first sweep's 200 trials are still running (no wall-clock bound, which a
        # loaded machine's interpreter start alone can exceed)
        assert first.poll() is None, "the second run waited for the first to finish"
        assert second.returncode == 2, second.stderr
        for part in (f"pid {first.pid}", socket.gethostname(), "simgrasp", "evaluate"):
            assert part in second.stderr, (part, second.stderr)
        assert "Traceback" not in second.stderr
    finally:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(first.pid, signal.SIGKILL)
        first.wait()
    # A SIGKILLed holder leaves no stuck lock: the next run takes it at once.
    with claim_out_dir(out, ["evaluate", "again"]):
        assert str(os.getpid()) in (out / LOCK_FILE).read_text()


def test_a_shared_cache_is_waited_for_not_refused(tmp_path: Path, capsys) -> None:
    """A suite's oracle is a cache that runs on different ``--out`` share: a claim with
    ``wait`` names the holder on stderr, blocks until it lets go, then takes the lock."""
    cache = tmp_path / "oracle"
    held, release = threading.Event(), threading.Event()
    order: list[str] = []

    def holder() -> None:
        with claim_out_dir(cache, ["bench", "oracle", "first"]):
            held.set()
            release.wait(TIMEOUT_S)
            order.append("holder done")

    def waiter() -> None:
        with claim_out_dir(cache, ["bench", "oracle", "second"], wait=True):
            order.append("waiter in")

    first = threading.Thread(target=holder)
    first.start()
    assert held.wait(TIMEOUT_S)
    second = threading.Thread(target=waiter)
    second.start()
    deadline = time.monotonic() + TIMEOUT_S
    err = ""
    while "waiting for" not in err:  # printed just before the claim blocks
        assert time.monotonic() < deadline, "the waiting claim never said it waits"
        err += capsys.readouterr().err
        time.sleep(0.05)
    assert f"pid {os.getpid()}" in err and "first" in err, err
    assert order == [], "the waiting claim entered while the lock was held"
    release.set()
    first.join(TIMEOUT_S)
    second.join(TIMEOUT_S)
    assert order == ["holder done", "waiter in"]
    with (  # without ``wait`` the same cache is refused while held
        pytest.raises(ValueError, match="in use by another run"),
        claim_out_dir(cache, ["x"]),
        claim_out_dir(cache, ["y"]),
    ):
        pass
