"""Which build of the native module this is: work split over machines must be done by one build."""
from __future__ import annotations

import functools
import hashlib


@functools.lru_cache(maxsize=1)
def build_hash() -> str:
    """A hash of the native module's file (16 hex digits): the same binary, the same hash.
    'unknown' when the module's file cannot be read."""
    try:
        from . import _native
        digest = hashlib.sha256()
        with open(_native.__file__, "rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                digest.update(block)
        return digest.hexdigest()[:16]
    except (ImportError, OSError, AttributeError):
        return "unknown"


class BuildMismatch(RuntimeError):
    """A worker's sphrect is another build than the client's."""


def check_same_build(client_hash: str) -> None:
    """On a worker: BuildMismatch unless this process's sphrect is the client's build (`client_hash`)."""
    if build_hash() != client_hash:
        import socket
        raise BuildMismatch(f"worker {socket.gethostname()} runs sphrect build {build_hash()}, the client build "
                            f"{client_hash}: install the same build on every worker")
