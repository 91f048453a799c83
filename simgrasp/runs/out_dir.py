"""Where a command writes: checked before any work starts; a sweep's output directory is also
held by one run at a time.

:func:`check_outputs` proves writable every path setting marked ``setting(output=...)``
(:func:`check_output_file`, :func:`check_out_dir`); the CLI calls it before a command runs.

:func:`claim_out_dir` refuses (``ValueError`` naming the directory) a path that is a file or a
directory this process cannot create or write into (it creates and deletes a probe file, and
opens an existing ``trials.jsonl`` for appending), then takes an exclusive ``flock`` on
``DIR/.simgrasp.lock`` for as long as the run lasts. The lock is held by the open file
descriptor, so the kernel releases it when its holder exits in any way, ``kill -9`` included:
a dead run never leaves the directory locked. The holder writes its pid, host, start time and
command line into the file, so a second run on the directory names the one that holds it; the
file outlives the run, so it also says which command wrote the directory last
(:func:`claim_out_dir`'s ``check`` reads it before the new run's replaces it). The holder also
records the library versions it runs under (:mod:`simgrasp.runs.versions`).
"""

from __future__ import annotations

import contextlib
import fcntl
import functools
import json
import os
import shlex
import socket
import sys
import time
from collections.abc import Callable, Iterator, Sequence
from pathlib import Path
from typing import Any

from simgrasp.errors import SimgraspError
from simgrasp.runs.versions import record_versions

LOCK_FILE = ".simgrasp.lock"
LOG_FILE = "trials.jsonl"


def check_out_dir(out: Path, option: str = "--out") -> None:
    """Create ``out`` if needed and prove it writable; a ValueError naming ``option`` and
    ``out`` otherwise."""
    out = Path(out)
    if out.exists() and not out.is_dir():
        raise SimgraspError(f"{option} {out}: is a file, not a directory")
    _refuse_file_in_the_way(out, option)
    try:
        out.mkdir(parents=True, exist_ok=True)
        probe = out / f".write-probe-{os.getpid()}"
        probe.write_bytes(b"probe")
        probe.unlink()
        log = out / LOG_FILE
        if log.exists() or log.is_symlink():
            with log.open("ab"):
                pass
    except OSError as exc:
        where = exc.filename or out
        raise SimgraspError(f"{option} {out}: {where} is not writable ({exc.strerror})") from None


def check_output_file(path: Path, option: str) -> None:
    """Prove a file can be written at ``path`` (its directory created if needed) before the
    work that makes it runs; a ValueError naming ``option`` and ``path`` otherwise."""
    path = Path(path)
    if path.is_dir():
        raise SimgraspError(f"{option} {path}: is a directory, not writable as a file")
    _refuse_file_in_the_way(path, option)
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        probe = path.parent / f".write-probe-{os.getpid()}"
        probe.write_bytes(b"probe")
        probe.unlink()
    except OSError as exc:
        raise SimgraspError(
            f"{option} {path}: its directory is not writable ({exc.strerror}: {exc.filename})"
        ) from None


def _refuse_file_in_the_way(path: Path, option: str) -> None:
    """Refuse ``path`` when one of its parents is a file (no folder can be made there)."""
    blocker = next((p for p in path.parents if p.exists() and not p.is_dir()), None)
    if blocker is not None:
        raise SimgraspError(f"{option} {path}: {blocker} is a file, not a directory")


def check_outputs(options: Any) -> list[Path]:
    """Prove writable, before any work, every path of the settings tree ``options`` whose
    field is marked ``setting(output="file" | "plot" | "dir")`` and is given (not None); a
    plot's suffix must be one matplotlib writes. Returns the folders it created, deepest
    first (:func:`remove_empty` takes them back when the run then fails)."""
    from simgrasp.config.arguments import flag_name
    from simgrasp.config.schema import leaves

    made: list[Path] = []
    for leaf in leaves(type(options)):
        if leaf.spec.output is None:
            continue
        value = functools.reduce(lambda node, name: getattr(node, name, None), leaf.path, options)
        if value is None:
            continue
        option = flag_name(leaf.key) if not leaf.spec.positional else leaf.key.upper()
        folder = Path(value) if leaf.spec.output == "dir" else Path(value).parent
        missing = [p for p in (folder, *folder.parents) if not p.exists()]
        if leaf.spec.output == "dir":
            check_out_dir(Path(value), option)
        else:
            if leaf.spec.output == "plot":
                check_plot_suffix(Path(value), option)
            if leaf.spec.suffixes and Path(value).suffix.lower() not in leaf.spec.suffixes:
                raise SimgraspError(
                    f"{option} {value}: expected a {' or '.join(leaf.spec.suffixes)} file"
                )
            check_output_file(Path(value), option)
        made = missing + made
    return made


def remove_empty(folders: Sequence[Path]) -> None:
    """Remove those of ``folders`` (deepest first) that are still empty: what
    :func:`check_outputs` made for a run that failed before writing there."""
    for folder in folders:
        with contextlib.suppress(OSError):  # not empty, or gone: left as it is
            folder.rmdir()


def check_plot_suffix(path: Path, option: str) -> None:
    """Refuse a picture path whose suffix matplotlib cannot write (``.txt``, none)."""
    from matplotlib.figure import Figure

    kinds = Figure().canvas.get_supported_filetypes()
    if path.suffix.lower().lstrip(".") not in kinds:
        raise SimgraspError(
            f"{option} {path}: a picture needs one of the suffixes .png, .pdf, .svg, .jpg "
            f"(or {', '.join(sorted(set(kinds) - {'png', 'pdf', 'svg', 'jpg'}))})"
        )


def _holder_text(command: Sequence[str]) -> str:
    when = time.strftime("%Y-%m-%d %H:%M:%S %Z", time.localtime())
    holder = {"pid": os.getpid(), "host": socket.gethostname(), "since": when}
    words = [*command]
    if words[:1] != ["simgrasp"]:  # invocation() names the program, tests may not
        words.insert(0, "simgrasp")
    return json.dumps({**holder, "command": shlex.join(words)}) + "\n"


def _recorded_command(lock_path: Path) -> str | None:
    """The sub-command (``evaluate``, ``demo``, ...) of the run a lock file names, or None
    when it names none (no file, an empty or unreadable one). Lock files of earlier versions
    name their command ``simgrasp simgrasp evaluate ...``."""
    try:
        words = shlex.split(json.loads(lock_path.read_text(encoding="utf-8"))["command"])
    except (OSError, ValueError, KeyError, TypeError, AttributeError):
        return None
    return next((word for word in words if word != "simgrasp"), None)


def _describe_holder(lock_path: Path) -> str:
    try:
        holder = json.loads(lock_path.read_text(encoding="utf-8"))
        return (
            f"pid {holder['pid']} on {holder['host']} since {holder['since']}: {holder['command']}"
        )
    except (OSError, ValueError, KeyError, TypeError):
        return "a process that has not written its name yet"


@contextlib.contextmanager
def claim_out_dir(
    out: Path,
    command: Sequence[str],
    check: Callable[[str | None], None] | None = None,
    wait: bool = False,
) -> Iterator[Path]:
    """Check ``out`` (:func:`check_out_dir`) and hold its lock while the block runs; a
    ValueError naming the running holder if another process holds it. ``command`` is this
    run's argument list (written into the lock file for a second run to name). ``check``, if
    given, is called under the lock with the sub-command of the run that held ``out`` last
    (None when none is recorded) before this run's replaces it: it may refuse the directory,
    which then keeps its record. ``wait`` is for a cache that runs on different ``--out``
    share (a suite's oracle): a held lock is waited for, with one line on stderr naming its
    holder, and the block then finds the holder's finished records instead of redoing them."""
    out = Path(out)
    check_out_dir(out)
    lock_path = out / LOCK_FILE
    fd = os.open(lock_path, os.O_RDWR | os.O_CREAT, 0o644)
    try:
        try:
            fcntl.flock(fd, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            if not wait:
                raise SimgraspError(
                    f"--out {out} is in use by another run ({_describe_holder(lock_path)}); "
                    "wait for it to finish or choose another --out"
                ) from None
            print(
                f"waiting for {out}, in use by another run ({_describe_holder(lock_path)})",
                file=sys.stderr,
            )
            fcntl.flock(fd, fcntl.LOCK_EX)
        if check is not None:
            check(_recorded_command(lock_path))
        os.ftruncate(fd, 0)
        os.write(fd, _holder_text(command).encode())
        os.fsync(fd)
        record_versions(out)
        yield out
    finally:
        os.close(fd)  # releases the lock
