"""Download YCB objects from the official site into the layout the loader reads.

One archive per object (``<id>_google_16k.tgz`` or ``<id>_berkeley_meshes.tgz``) is
downloaded into ``<dest>/.downloads/<archive>.part``, resuming with an HTTP Range request if a
previous attempt was interrupted; its size is checked against the server's Content-Length,
its MD5 against the ETag when the server gives a plain-MD5 ETag (S3 does for these files),
and the gzip stream and tar listing are read in full. It is then unpacked into a temporary
folder beside the destination and renamed into place, so an interrupted or rejected download
never leaves a half-unpacked object behind. Objects whose scan folder already exists are
skipped.
"""

from __future__ import annotations

import gzip
import hashlib
import http.client
import os
import re
import shutil
import socket
import tarfile
import tempfile
import urllib.error
import urllib.parse
import urllib.request
import zlib
from dataclasses import dataclass
from pathlib import Path, PurePosixPath
from typing import Literal

from tqdm import tqdm

from simgrasp.assets.ycb_catalog import YCB_CATALOG, find_ycb_entry
from simgrasp.errors import SimgraspError

YCB_BASE_URL = "http://ycb-benchmarks.s3-website-us-east-1.amazonaws.com/data"
ArchiveKind = Literal["google_16k", "berkeley"]
# The folder an archive of each kind unpacks to, inside ``<dest>/<object_id>/``.
SCAN_DIR: dict[str, str] = {"google_16k": "google_16k", "berkeley": "poisson"}
DOWNLOADS_DIR = ".downloads"
CHUNK_BYTES = 1 << 16


class FetchError(Exception):
    """A download that failed; the message says which object, what went wrong and what to do."""


class ServerUnreachable(FetchError):
    """The server could not be reached at all (offline, unknown host, refused, timed out)."""


@dataclass(frozen=True)
class FetchResult:
    """Outcome for one object: ``path`` is ``<dest>/<object_id>``."""

    object_id: str
    status: Literal["downloaded", "present"]
    path: Path


URL_SCHEMES = ("http", "https", "file")
"""What ``base_url`` may start with (``file://`` for a local mirror)."""


def check_base_url(base_url: str) -> None:
    """Refuse a ``base_url`` that is no URL the download can open (no scheme, another scheme,
    or a web address without its host)."""
    parts = urllib.parse.urlsplit(base_url)
    if parts.scheme not in URL_SCHEMES or (parts.scheme != "file" and not parts.netloc):
        raise SimgraspError(f"--base-url {base_url}: not a URL (http://, https://, file://)")


def archive_url(object_id: str, kind: ArchiveKind, base_url: str = YCB_BASE_URL) -> str:
    """The official archive URL of one object (``base_url`` replaces the site's ``/data``)."""
    base = base_url.rstrip("/")
    if kind == "google_16k":
        return f"{base}/google/{object_id}_google_16k.tgz"
    if kind == "berkeley":
        return f"{base}/berkeley/{object_id}/{object_id}_berkeley_meshes.tgz"
    raise SimgraspError(f"unknown archive kind {kind!r} (expected 'google_16k' or 'berkeley')")


def resolve_object_ids(spec: str, kind: ArchiveKind) -> list[str]:
    """Catalog ids from ``"all"`` or a comma-separated list of ids or bare names.

    ``"all"`` means every catalog object that has a scan of ``kind``; naming an object
    without one is an error.
    """
    scan = SCAN_DIR[kind]
    if spec.strip().lower() == "all":
        return [e.id for e in YCB_CATALOG if scan in e.scans]
    names = [part.strip() for part in spec.split(",") if part.strip()]
    if not names:
        raise SimgraspError("--objects is empty: give YCB ids (e.g. 025_mug,048_hammer) or 'all'")
    entries = [find_ycb_entry(name) for name in names]
    for entry in entries:
        if scan not in entry.scans:
            raise SimgraspError(f"YCB object {entry.id!r} has no {scan} scan; use --kind berkeley")
    return list(dict.fromkeys(e.id for e in entries))


def _describe_url_error(exc: urllib.error.URLError, url: str, timeout: float) -> str:
    host = urllib.parse.urlsplit(url).hostname or url
    reason = exc.reason
    if isinstance(reason, socket.gaierror):
        return f"cannot resolve host {host} (offline, or a wrong --base-url?)"
    if isinstance(reason, ConnectionRefusedError):
        return f"cannot connect to {host}: connection refused"
    if isinstance(reason, TimeoutError):
        return f"no answer from {host} within {timeout:g} s"
    return f"cannot reach {url}: {reason}"


def _open(url: str, offset: int, timeout: float) -> http.client.HTTPResponse:
    headers = {"User-Agent": "simgrasp-fetch-ycb"}
    if offset:
        headers["Range"] = f"bytes={offset}-"
    request = urllib.request.Request(url, headers=headers)
    try:
        return urllib.request.urlopen(request, timeout=timeout)
    except urllib.error.HTTPError:
        raise  # the server answered; the caller reports the status
    except urllib.error.URLError as exc:
        raise ServerUnreachable(_describe_url_error(exc, url, timeout)) from None
    except TimeoutError:
        host = urllib.parse.urlsplit(url).hostname
        raise ServerUnreachable(f"no answer from {host} within {timeout:g} s") from None
    except ValueError as exc:
        raise FetchError(f"invalid URL {url!r}: {exc} (check --base-url)") from None


def _expected_md5(response: http.client.HTTPResponse) -> str | None:
    """The MD5 a plain (non-multipart) S3-style ETag carries, if any."""
    etag = (response.headers.get("ETag") or "").strip('"')
    return etag.lower() if re.fullmatch(r"[0-9a-fA-F]{32}", etag) else None


def _total_size(response: http.client.HTTPResponse, offset: int, label: str) -> int | None:
    """The full archive size in bytes, from Content-Range (resumed) or Content-Length."""
    if response.status == 206:
        match = re.fullmatch(r"bytes (\d+)-\d+/(\d+)", response.headers.get("Content-Range", ""))
        if match is None or int(match.group(1)) != offset:
            raise FetchError(
                f"{label}: server answered a resume request for {response.url} with an unexpected "
                f"range {response.headers.get('Content-Range')!r}"
            )
        return int(match.group(2))
    length = response.headers.get("Content-Length")
    return int(length) if length is not None else None


def download_resumable(
    url: str, part_path: Path, *, label: str, timeout: float = 30.0, progress: bool = True
) -> str | None:
    """Download ``url`` into ``part_path``, continuing an existing partial file.

    Returns the MD5 the server advertised (ETag), or ``None``. Raises :class:`FetchError`
    on HTTP and network errors, and when fewer bytes than announced arrived (the partial
    file is kept so that the next run resumes).
    """
    offset = part_path.stat().st_size if part_path.exists() else 0
    try:
        response = _open(url, offset, timeout)
    except FetchError as exc:
        raise type(exc)(f"{label}: {exc}") from None
    except urllib.error.HTTPError as exc:
        if exc.code == 416 and offset:
            # The partial file is not a prefix the server can continue: start again.
            part_path.unlink()
            return download_resumable(
                url, part_path, label=label, timeout=timeout, progress=progress
            )
        hint = " (no such archive: check the object id and --kind)" if exc.code == 404 else ""
        raise FetchError(f"{label}: {url} answered HTTP {exc.code} {exc.reason}{hint}") from None
    part_path.parent.mkdir(parents=True, exist_ok=True)
    with response:
        if response.status != 206:
            offset = 0  # the server ignored the Range header: restart from scratch
        total = _total_size(response, offset, label)
        expected_md5 = _expected_md5(response)
        received = _append_body(response, part_path, offset, total, label, progress)
    if total is not None and received != total:
        raise FetchError(
            f"{label}: download interrupted after {received} of {total} bytes ({url}); run "
            "the command again to resume"
        )
    return expected_md5


def _append_body(
    response: http.client.HTTPResponse,
    part_path: Path,
    offset: int,
    total: int | None,
    label: str,
    progress: bool,
) -> int:
    """Stream ``response`` onto ``part_path`` (after its first ``offset`` bytes, or afresh for
    0) with a progress bar; returns the bytes the file then holds."""
    received = offset
    with (
        part_path.open("ab" if offset else "wb") as out,
        tqdm(
            total=total,
            initial=offset,
            unit="B",
            unit_scale=True,
            unit_divisor=1024,
            desc=label,
            disable=not progress,
        ) as bar,
    ):
        while True:
            try:
                chunk = response.read(CHUNK_BYTES)
            except (http.client.IncompleteRead, OSError) as exc:
                raise FetchError(
                    f"{label}: download interrupted after {received} of {total or '?'} "
                    f"bytes ({type(exc).__name__}); run the command again to resume"
                ) from None
            if not chunk:
                break
            out.write(chunk)
            received += len(chunk)
            bar.update(len(chunk))
    return received


def _file_md5(path: Path) -> str:
    digest = hashlib.md5(usedforsecurity=False)
    with path.open("rb") as f:
        while block := f.read(1 << 20):
            digest.update(block)
    return digest.hexdigest()


def verify_archive(archive: Path, object_id: str, scan_dir: str) -> list[str]:
    """Read the whole archive and return its member names, or raise :class:`FetchError`.

    Checks the gzip stream end to end (CRC and length), lists and reads every tar member,
    and requires every member to lie inside ``<object_id>/`` (no absolute paths, no
    ``..``, no links) with at least one file under ``<object_id>/<scan_dir>/``.
    """
    try:
        with gzip.open(archive, "rb") as stream:
            while stream.read(1 << 20):
                pass
        names = []
        with tarfile.open(archive, "r:gz") as tar:
            for member in tar:
                parts = PurePosixPath(member.name).parts
                if PurePosixPath(member.name).is_absolute() or ".." in parts:
                    raise FetchError(f"unsafe path {member.name!r}")
                if not parts or parts[0] != object_id:
                    raise FetchError(f"member {member.name!r} is outside {object_id}/")
                if member.issym() or member.islnk():
                    raise FetchError(f"link member {member.name!r}")
                extracted = tar.extractfile(member) if member.isfile() else None
                if extracted is not None:
                    while extracted.read(1 << 20):
                        pass
                    names.append(member.name)
    except FetchError as exc:
        raise FetchError(f"{object_id}: archive {archive.name} rejected: {exc}") from None
    except (OSError, EOFError, tarfile.TarError, zlib.error) as exc:
        raise FetchError(
            f"{object_id}: archive {archive.name} is corrupt ({type(exc).__name__}: {exc})"
        ) from None
    if not any(PurePosixPath(n).parts[1:2] == (scan_dir,) for n in names):
        raise FetchError(f"{object_id}: archive {archive.name} has no files in {scan_dir}/")
    return names


def unpack_atomically(archive: Path, dest: Path, object_id: str) -> Path:
    """Unpack a verified archive into ``dest/<object_id>`` without ever exposing a partial one.

    Extraction happens in a hidden temporary folder in ``dest``; finished folders are then
    renamed into place (the whole object folder if it is new, else each new scan folder).
    """
    staging = Path(tempfile.mkdtemp(prefix=f".{object_id}.unpacking-", dir=dest))
    target = dest / object_id
    try:
        with tarfile.open(archive, "r:gz") as tar:
            tar.extractall(staging, filter="data")
        unpacked = staging / object_id
        if not target.exists():
            os.rename(unpacked, target)
        else:
            for child in sorted(unpacked.iterdir()):
                if not (target / child.name).exists():
                    os.rename(child, target / child.name)
    finally:
        shutil.rmtree(staging, ignore_errors=True)
    return target


def _remove_stale_staging(dest: Path, object_id: str) -> None:
    for stale in dest.glob(f".{object_id}.unpacking-*"):
        shutil.rmtree(stale, ignore_errors=True)


def fetch_object(
    object_id: str,
    dest: Path,
    kind: ArchiveKind = "google_16k",
    *,
    base_url: str = YCB_BASE_URL,
    timeout: float = 30.0,
    progress: bool = True,
) -> FetchResult:
    """Download and unpack one object unless ``dest/<id>/<scan folder>`` already exists."""
    scan_dir = SCAN_DIR[kind]
    target = dest / object_id
    if (target / scan_dir).is_dir():
        return FetchResult(object_id, "present", target)
    dest.mkdir(parents=True, exist_ok=True)
    url = archive_url(object_id, kind, base_url)
    downloads = dest / DOWNLOADS_DIR
    archive = downloads / PurePosixPath(urllib.parse.urlsplit(url).path).name
    part = archive.with_name(archive.name + ".part")
    _remove_stale_staging(dest, object_id)
    if not archive.exists():
        expected_md5 = download_resumable(
            url, part, label=object_id, timeout=timeout, progress=progress
        )
        if expected_md5 is not None and _file_md5(part) != expected_md5:
            part.unlink()
            raise FetchError(
                f"{object_id}: checksum mismatch for {url} (MD5 differs from the server's "
                "ETag); the download was deleted, run the command again"
            )
        os.replace(part, archive)
    try:
        verify_archive(archive, object_id, scan_dir)
    except FetchError as exc:
        archive.unlink()
        raise FetchError(f"{exc}; it was deleted, run the command again") from None
    unpack_atomically(archive, dest, object_id)
    archive.unlink()
    if not any(downloads.iterdir()):
        downloads.rmdir()
    return FetchResult(object_id, "downloaded", target)
