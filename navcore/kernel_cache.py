"""Drop cached kernels that may hold another file's old code.

numba keeps a kernel's machine code in its cache and checks it against the kernel's own source
file only. A kernel that calls a kernel of another module carries the callee's machine code in
its own: after the callee's file changes (a ``git pull``, an edit) and the caller's does not, the
cached caller would run the old callee. So, once per process and before any kernel loads, the
size and modification time of every source file of the packages that hold kernels are compared
with the stamp written last time; when they differ, navbt's cache files are removed and every
kernel compiles afresh on first use. (A pip upgrade rewrites every file, which numba notices by
itself; this is for checkouts.)

The cache files are where numba puts them: ``__pycache__`` beside each source file, or, with
``NUMBA_CACHE_DIR``, that directory's ``<folder>_<sha1 of the folder's path>`` mirror of it.
Only ``.nbi`` / ``.nbc`` files (numba's index and code) are removed.
"""

from __future__ import annotations

import hashlib
import os

# the packages whose modules define kernels (navcore/ and hw/, beside this file's package)
KERNEL_PACKAGES = ("navcore", "hw")
STAMP_NAME = "navbt-kernels.stamp"


def source_dirs(root: str, packages: tuple[str, ...] = KERNEL_PACKAGES) -> list[str]:
    """Every folder below ``root``/<package> that holds Python sources (not caches)."""
    out = []
    for package in packages:
        for d, subdirs, files in os.walk(os.path.join(root, package)):
            subdirs[:] = sorted(s for s in subdirs if s != "__pycache__")
            if any(f.endswith(".py") for f in files):
                out.append(d)
    return out


def sources_stamp(dirs: list[str]) -> str:
    """One digest of the name, size and modification time of every ``.py`` file in ``dirs``."""
    h = hashlib.sha1()
    for d in dirs:
        for f in sorted(os.listdir(d)):
            if f.endswith(".py"):
                st = os.stat(os.path.join(d, f))
                h.update(f"{d}/{f}:{st.st_size}:{st.st_mtime_ns}\n".encode())
    return h.hexdigest()


def cache_dirs(dirs: list[str], cache_root: str | None) -> list[str]:
    """Where numba keeps the cache files of the kernels defined in ``dirs``."""
    if cache_root:
        return [os.path.join(cache_root, f"{os.path.basename(d)}_"
                             f"{hashlib.sha1(os.path.abspath(d).encode()).hexdigest()}")
                for d in dirs]
    return [os.path.join(d, "__pycache__") for d in dirs]


def refresh(dirs: list[str], cache_root: str | None, stamp_path: str) -> bool:
    """Remove the cache files of ``dirs`` when their sources changed since the stamp at
    ``stamp_path`` was written, and write the new stamp; True if they were removed. Folders
    that cannot be read or written are left alone (numba then caches elsewhere or not)."""
    stamp = sources_stamp(dirs)
    try:
        with open(stamp_path, encoding="ascii") as f:
            if f.read() == stamp:
                return False
    except OSError:
        pass
    for c in cache_dirs(dirs, cache_root):
        try:
            names = os.listdir(c)
        except OSError:
            continue
        for name in names:
            if name.endswith((".nbi", ".nbc")):
                try:
                    os.remove(os.path.join(c, name))
                except OSError:
                    pass
    try:
        os.makedirs(os.path.dirname(stamp_path), exist_ok=True)
        tmp = f"{stamp_path}.{os.getpid()}"
        with open(tmp, "w", encoding="ascii") as f:
            f.write(stamp)
        os.replace(tmp, stamp_path)
    except OSError:
        pass
    return True


def cache_probe() -> int:
    """The body of the kernel whose presence in numba's cache tells whether navbt's kernels
    were compiled here yet (``executive.commands.warmup_cmd.kernels_cold``); it lives in a kernel
    package so that ``refresh`` drops it with the others."""
    return 1


def refresh_navbt() -> bool:
    """``refresh`` for navbt's own kernel packages and numba's cache location (the
    ``NUMBA_CACHE_DIR`` numba reads when it is imported)."""
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    dirs = source_dirs(root)
    cache_root = os.environ.get("NUMBA_CACHE_DIR") or None
    stamp_dir = (cache_root if cache_root
                 else os.path.join(root, KERNEL_PACKAGES[0], "__pycache__"))
    key = hashlib.sha1(root.encode()).hexdigest()[:12]
    return refresh(dirs, cache_root, os.path.join(stamp_dir, f"{key}-{STAMP_NAME}"))
