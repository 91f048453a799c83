"""`simgrasp fetch-ycb` against a local HTTP server (Range support) serving archives built here.

Never touches the internet: the server listens on 127.0.0.1, the unresolvable host is in the
reserved ``.invalid`` domain.
"""

from __future__ import annotations

import hashlib
import io
import socket
import tarfile
import threading
from collections.abc import Iterator
from dataclasses import dataclass, field
from http.server import BaseHTTPRequestHandler, ThreadingHTTPServer
from pathlib import Path

import pytest
import trimesh

from simgrasp.assets.fetch import (
    ArchiveKind,
    FetchError,
    FetchResult,
    archive_url,
    fetch_object,
    resolve_object_ids,
)
from simgrasp.assets.mesh_check import load_mesh_file
from simgrasp.assets.ycb import ycb_mesh_path
from simgrasp.cli import main

GOOGLE_MUG = "/google/025_mug_google_16k.tgz"


def _obj_text() -> str:
    box = trimesh.creation.box(extents=(0.09, 0.08, 0.1))
    lines = ["mtllib textured.mtl", "usemtl material_0"]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in box.vertices]
    lines += [f"f {a + 1} {b + 1} {c + 1}" for a, b, c in box.faces]
    return "\n".join(lines) + "\n"


def _targz(files: dict[str, bytes]) -> bytes:
    buffer = io.BytesIO()
    with tarfile.open(fileobj=buffer, mode="w:gz") as tar:
        for name, data in files.items():
            info = tarfile.TarInfo(name)
            info.size = len(data)
            tar.addfile(info, io.BytesIO(data))
    return buffer.getvalue()


def _google_archive(object_id: str) -> bytes:
    scan = f"{object_id}/google_16k"
    return _targz(
        {
            f"{scan}/textured.obj": _obj_text().encode(),
            f"{scan}/textured.mtl": b"newmtl material_0\nmap_Kd texture_map.png \n",
            f"{scan}/texture_map.png": b"\x89PNG not decoded by the loader",
        }
    )


@dataclass
class ArchiveServer:
    """Serves ``files`` (URL path -> bytes) with Range support; records every request."""

    files: dict[str, bytes] = field(default_factory=dict)
    requests: list[tuple[str, str | None]] = field(default_factory=list)
    cut_after: int | None = None  # send only this many body bytes once, then hang up
    etag_override: str | None = None
    ignore_range: bool = False  # answer every request with the whole file (200)
    url: str = ""


def _handler(state: ArchiveServer) -> type[BaseHTTPRequestHandler]:
    class Handler(BaseHTTPRequestHandler):
        def log_message(self, format: str, *args: object) -> None:  # noqa: A002
            pass

        def do_GET(self) -> None:  # noqa: N802 (http.server API)
            range_header = self.headers.get("Range")
            state.requests.append((self.path, range_header))
            if state.ignore_range:
                range_header = None
            data = state.files.get(self.path)
            if data is None:
                self.send_error(404, "Not Found")
                return
            start = int(range_header.removeprefix("bytes=").rstrip("-")) if range_header else 0
            if start >= len(data) and range_header:
                self.send_response(416)
                self.send_header("Content-Range", f"bytes */{len(data)}")
                self.send_header("Content-Length", "0")
                self.end_headers()
                return
            body = data[start:]
            self.send_response(206 if range_header else 200)
            if range_header:
                self.send_header("Content-Range", f"bytes {start}-{len(data) - 1}/{len(data)}")
            self.send_header("Content-Length", str(len(body)))
            etag = state.etag_override or hashlib.md5(data).hexdigest()
            self.send_header("ETag", f'"{etag}"')
            self.end_headers()
            if state.cut_after is not None:
                body, state.cut_after = body[: state.cut_after], None
                self.close_connection = True
            self.wfile.write(body)

    return Handler


@pytest.fixture
def server() -> Iterator[ArchiveServer]:
    state = ArchiveServer(files={GOOGLE_MUG: _google_archive("025_mug")})
    httpd = ThreadingHTTPServer(("127.0.0.1", 0), _handler(state))
    state.url = f"http://127.0.0.1:{httpd.server_address[1]}"
    thread = threading.Thread(target=httpd.serve_forever, args=(0.05,), daemon=True)
    thread.start()
    yield state
    httpd.shutdown()
    httpd.server_close()


def _fetch(
    server: ArchiveServer, dest: Path, object_id: str = "025_mug", kind: ArchiveKind = "google_16k"
) -> FetchResult:
    return fetch_object(object_id, dest, kind, base_url=server.url, progress=False, timeout=5)


def _assert_nothing_unpacked(dest: Path, object_id: str = "025_mug") -> None:
    assert not (dest / object_id).exists()
    assert not list(dest.glob(f".{object_id}.unpacking-*"))


def test_download_unpacks_into_the_loader_layout(server: ArchiveServer, tmp_path: Path) -> None:
    dest = tmp_path / "ycb"
    result = _fetch(server, dest)
    assert result.status == "downloaded"
    assert result.path == dest / "025_mug"
    assert server.requests == [(GOOGLE_MUG, None)]
    mesh_path, texture_path = ycb_mesh_path(dest, "025_mug")
    assert mesh_path == dest / "025_mug" / "google_16k" / "textured.obj"
    assert texture_path == dest / "025_mug" / "google_16k" / "texture_map.png"
    mesh = load_mesh_file(mesh_path, "025_mug")
    assert mesh.is_watertight
    assert mesh.extents.max() == pytest.approx(0.1)
    # No archive, partial file or staging folder left behind.
    assert sorted(p.name for p in dest.iterdir()) == ["025_mug"]


def test_resume_after_truncated_part_file(server: ArchiveServer, tmp_path: Path) -> None:
    data = server.files[GOOGLE_MUG]
    half = len(data) // 2
    part = tmp_path / ".downloads" / "025_mug_google_16k.tgz.part"
    part.parent.mkdir(parents=True)
    part.write_bytes(data[:half])
    assert _fetch(server, tmp_path).status == "downloaded"
    assert server.requests == [(GOOGLE_MUG, f"bytes={half}-")]
    obj = (tmp_path / "025_mug" / "google_16k" / "textured.obj").read_text()
    assert obj == _obj_text()


def test_interrupted_download_keeps_part_and_next_run_resumes(
    server: ArchiveServer, tmp_path: Path
) -> None:
    data = server.files[GOOGLE_MUG]
    server.cut_after = 300
    with pytest.raises(FetchError, match=r"025_mug: download interrupted after 300 of \d+ bytes"):
        _fetch(server, tmp_path)
    _assert_nothing_unpacked(tmp_path)
    part = tmp_path / ".downloads" / "025_mug_google_16k.tgz.part"
    assert part.read_bytes() == data[:300]

    assert _fetch(server, tmp_path).status == "downloaded"
    assert server.requests[-1] == (GOOGLE_MUG, "bytes=300-")
    assert (tmp_path / "025_mug" / "google_16k" / "textured.obj").read_text() == _obj_text()


def test_part_longer_than_archive_restarts(server: ArchiveServer, tmp_path: Path) -> None:
    data = server.files[GOOGLE_MUG]
    part = tmp_path / ".downloads" / "025_mug_google_16k.tgz.part"
    part.parent.mkdir(parents=True)
    stale = data + b"stale bytes of another version"
    part.write_bytes(stale)
    assert _fetch(server, tmp_path).status == "downloaded"
    assert server.requests == [(GOOGLE_MUG, f"bytes={len(stale)}-"), (GOOGLE_MUG, None)]


def test_server_ignoring_range_restarts_from_scratch(server: ArchiveServer, tmp_path: Path) -> None:
    data = server.files[GOOGLE_MUG]
    server.ignore_range = True
    part = tmp_path / ".downloads" / "025_mug_google_16k.tgz.part"
    part.parent.mkdir(parents=True)
    part.write_bytes(data[:100])
    assert _fetch(server, tmp_path).status == "downloaded"
    assert server.requests == [(GOOGLE_MUG, "bytes=100-")]
    assert (tmp_path / "025_mug" / "google_16k" / "textured.obj").read_text() == _obj_text()


def _flip_middle_byte(data: bytes) -> bytes:
    middle = len(data) // 2
    return data[:middle] + bytes([data[middle] ^ 0xFF]) + data[middle + 1 :]


@pytest.mark.parametrize(
    "corrupt",
    [
        _flip_middle_byte,
        lambda data: data[: len(data) // 2],
        lambda data: b"<html>Access denied</html>" * 20,
    ],
    ids=["flipped-byte", "truncated-gzip", "not-gzip"],
)
def test_corrupt_archive_rejected_nothing_unpacked(
    server: ArchiveServer, tmp_path: Path, corrupt
) -> None:
    server.files[GOOGLE_MUG] = corrupt(server.files[GOOGLE_MUG])
    with pytest.raises(FetchError, match=r"025_mug: archive 025_mug_google_16k\.tgz is corrupt"):
        _fetch(server, tmp_path)
    _assert_nothing_unpacked(tmp_path)
    assert not list((tmp_path / ".downloads").iterdir())  # rejected archive deleted


def test_checksum_mismatch_rejected(server: ArchiveServer, tmp_path: Path) -> None:
    server.etag_override = "0" * 32
    with pytest.raises(FetchError, match=r"025_mug: checksum mismatch"):
        _fetch(server, tmp_path)
    _assert_nothing_unpacked(tmp_path)


@pytest.mark.parametrize(
    ("member", "reason"),
    [
        ("../escaped.txt", "unsafe path"),
        ("025_mug/../../escaped.txt", "unsafe path"),
        ("048_hammer/google_16k/textured.obj", "outside 025_mug/"),
    ],
)
def test_archive_with_paths_outside_the_object_rejected(
    server: ArchiveServer, tmp_path: Path, member: str, reason: str
) -> None:
    server.files[GOOGLE_MUG] = _targz(
        {"025_mug/google_16k/textured.obj": _obj_text().encode(), member: b"x"}
    )
    dest = tmp_path / "ycb"
    with pytest.raises(FetchError, match=rf"025_mug: archive .* rejected: .*{reason}"):
        _fetch(server, dest)
    _assert_nothing_unpacked(dest)
    assert not (tmp_path / "escaped.txt").exists()


def test_archive_without_the_scan_folder_rejected(server: ArchiveServer, tmp_path: Path) -> None:
    server.files[GOOGLE_MUG] = _targz({"025_mug/poisson/nontextured.stl": b"solid\n"})
    with pytest.raises(FetchError, match=r"has no files in google_16k/"):
        _fetch(server, tmp_path)
    _assert_nothing_unpacked(tmp_path)


def test_present_object_is_skipped_without_a_request(server: ArchiveServer, tmp_path: Path) -> None:
    (tmp_path / "025_mug" / "google_16k").mkdir(parents=True)
    result = _fetch(server, tmp_path)
    assert result.status == "present"
    assert server.requests == []


def test_berkeley_meshes_added_beside_an_existing_google_scan(
    server: ArchiveServer, tmp_path: Path
) -> None:
    stl = io.BytesIO()
    trimesh.creation.cylinder(radius=0.04, height=0.25).export(stl, file_type="stl")
    url_path = "/berkeley/025_mug/025_mug_berkeley_meshes.tgz"
    server.files[url_path] = _targz({"025_mug/poisson/nontextured.stl": stl.getvalue()})
    _fetch(server, tmp_path)
    result = _fetch(server, tmp_path, kind="berkeley")
    assert result.status == "downloaded"
    assert (tmp_path / "025_mug" / "google_16k" / "textured.obj").is_file()
    assert (tmp_path / "025_mug" / "poisson" / "nontextured.stl").is_file()
    assert server.requests[-1] == (url_path, None)


def test_http_404_is_a_clear_error(server: ArchiveServer, tmp_path: Path) -> None:
    with pytest.raises(
        FetchError, match=r"048_hammer: .*048_hammer_google_16k\.tgz answered HTTP 404"
    ):
        _fetch(server, tmp_path, object_id="048_hammer")
    _assert_nothing_unpacked(tmp_path, "048_hammer")


def _free_port() -> int:
    with socket.socket() as sock:
        sock.bind(("127.0.0.1", 0))
        return sock.getsockname()[1]


def test_refused_connection_is_a_clear_error(tmp_path: Path) -> None:
    url = f"http://127.0.0.1:{_free_port()}/data"
    with pytest.raises(
        FetchError, match=r"^025_mug: cannot connect to 127\.0\.0\.1: connection refused"
    ):
        fetch_object("025_mug", tmp_path, base_url=url, progress=False, timeout=5)


def test_unresolvable_host_is_a_clear_error(tmp_path: Path) -> None:
    with pytest.raises(
        FetchError, match=r"^025_mug: cannot resolve host ycb-mirror\.invalid \(offline"
    ):
        fetch_object("025_mug", tmp_path, base_url="http://ycb-mirror.invalid/data", progress=False)


def test_official_url_patterns() -> None:
    assert archive_url("025_mug", "google_16k") == (
        "http://ycb-benchmarks.s3-website-us-east-1.amazonaws.com/data/google/"
        "025_mug_google_16k.tgz"
    )
    assert archive_url("001_chips_can", "berkeley") == (
        "http://ycb-benchmarks.s3-website-us-east-1.amazonaws.com/data/berkeley/"
        "001_chips_can/001_chips_can_berkeley_meshes.tgz"
    )


def test_object_selection() -> None:
    assert resolve_object_ids("mug, 048_hammer,mug", "google_16k") == ["025_mug", "048_hammer"]
    google = resolve_object_ids("all", "google_16k")
    assert "001_chips_can" not in google
    assert "025_mug" in google
    assert "001_chips_can" in resolve_object_ids("all", "berkeley")
    with pytest.raises(ValueError, match=r"'001_chips_can' has no google_16k scan"):
        resolve_object_ids("chips_can", "google_16k")


def test_cli_downloads_and_reports(
    server: ArchiveServer, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    server.files["/google/048_hammer_google_16k.tgz"] = _google_archive("048_hammer")
    argv = ["fetch-ycb", "--objects", "mug,hammer", "--dest", str(tmp_path)]
    argv += ["--base-url", server.url, "--no-progress"]
    assert main(argv) == 0
    out = capsys.readouterr().out
    assert "025_mug: downloaded" in out and "048_hammer: downloaded" in out
    assert main(argv) == 0
    assert "025_mug: present" in capsys.readouterr().out


def test_cli_offline_error_without_traceback(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["fetch-ycb", "--objects", "mug,hammer,spatula", "--dest", str(tmp_path)]
    argv += ["--no-progress", "--base-url", f"http://127.0.0.1:{_free_port()}/data"]
    assert main(argv) == 1
    err = capsys.readouterr().err
    assert "error: 025_mug: cannot connect to 127.0.0.1: connection refused" in err
    assert "stopped; 2 more not tried" in err
    assert err.count("error:") == 1
    assert "Traceback" not in err
    assert not any(tmp_path.iterdir())


def test_cli_continues_after_a_missing_archive(
    server: ArchiveServer, tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["fetch-ycb", "--objects", "hammer,mug", "--dest", str(tmp_path), "--no-progress"]
    assert main([*argv, "--base-url", server.url]) == 1
    captured = capsys.readouterr()
    assert "048_hammer: " in captured.err and "HTTP 404" in captured.err
    assert "1 of 2 objects failed: 048_hammer" in captured.err
    assert "025_mug: downloaded" in captured.out


def test_cli_rejects_object_without_scan(
    tmp_path: Path, capsys: pytest.CaptureFixture[str]
) -> None:
    argv = ["fetch-ycb", "--objects", "chips_can", "--dest", str(tmp_path)]
    assert main(argv) == 2
    assert "no google_16k scan; use --kind berkeley" in capsys.readouterr().err
