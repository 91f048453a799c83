"""``simgrasp view`` on the command line: ``--port`` really serves the page on 127.0.0.1, and
a PATH it cannot show (no kind, a trial record without ``--record``) is one line."""

from __future__ import annotations

import json
import os
import socket
import subprocess
import sys
import time
import urllib.error
import urllib.request
from pathlib import Path

import pytest

ENV = {**os.environ, "PYTHONPATH": str(Path(__file__).resolve().parents[1])}


def _simgrasp(*args: str, cwd: Path, check: bool = True) -> subprocess.CompletedProcess[str]:
    return subprocess.run(
        [sys.executable, "-m", "simgrasp", *args], cwd=cwd, env=ENV, check=check,
        capture_output=True, text=True,
    )  # fmt: skip


@pytest.fixture(scope="module")
def trial_record(tmp_path_factory) -> Path:
    work = tmp_path_factory.mktemp("view-cli")
    done = _simgrasp("trial", "gen_hammer", "--record", "--json", cwd=work)
    (work / "t.json").write_text(done.stdout)
    return work / "t.json"


def _free_port() -> int:
    with socket.socket() as probe:
        probe.bind(("127.0.0.1", 0))
        return int(probe.getsockname()[1])


def test_view_port_serves_the_page_on_localhost(trial_record):
    port = _free_port()
    server = subprocess.Popen(
        [sys.executable, "-m", "simgrasp", "view", str(trial_record), "--port", str(port)],
        env=ENV, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True,
    )  # fmt: skip
    try:
        deadline, page = time.time() + 90, None
        while page is None:
            assert server.poll() is None, server.stderr.read() if server.stderr else ""
            assert time.time() < deadline, "the server never answered"
            try:
                with urllib.request.urlopen(f"http://127.0.0.1:{port}/", timeout=5) as answer:
                    assert answer.status == 200
                    assert answer.headers["Content-Type"].startswith("text/html")
                    page = answer.read().decode()
            except (ConnectionError, urllib.error.URLError):
                time.sleep(0.5)
        assert "<title>gen_hammer_s0: trial seed 0" in page
        assert 'id="slider"' in page and "window.SIMGRASP" in page and "window.showFrame" in page
        with pytest.raises(urllib.error.HTTPError):
            urllib.request.urlopen(f"http://127.0.0.1:{port}/other", timeout=5)
    finally:
        server.terminate()
        server.wait(timeout=10)


def test_view_refuses_what_it_cannot_show(trial_record, tmp_path):
    unknown = _simgrasp("view", str(tmp_path), "--export", "x.html", cwd=tmp_path, check=False)
    assert unknown.returncode == 2 and len(unknown.stderr.strip().splitlines()) == 1
    assert "label-grasps output folder" in unknown.stderr and "trial record" in unknown.stderr
    record = json.loads(trial_record.read_text())
    del record["replay"]
    (tmp_path / "plain.json").write_text(json.dumps(record))
    plain = _simgrasp("view", "plain.json", "--export", "x.html", cwd=tmp_path, check=False)
    assert plain.returncode == 2 and len(plain.stderr.strip().splitlines()) == 1
    assert "rerun the trial with --record" in plain.stderr
    record["replay"], record["failure"] = None, "no_grasp"  # the chain found no grasp
    (tmp_path / "none.json").write_text(json.dumps(record))
    none = _simgrasp("view", "none.json", "--export", "x.html", cwd=tmp_path, check=False)
    assert none.returncode == 2 and "nothing to replay" in none.stderr
    assert not (tmp_path / "x.html").exists()
