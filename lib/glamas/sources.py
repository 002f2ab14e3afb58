"""The hash of the library's kernel sources, and numba's compiled-kernel cache kept in step with it.

numba's on-disk cache (``cache=True``) keys a kernel on its own file only: after an edit to a
function it calls in *another* file, it would serve the old machine code. :func:`refresh_kernel_cache`
keeps a stamp file with the hash of the kernel sources (:func:`kernel_source_files`: every module
that imports numba, and every module of glamas they import, directly or not) beside the cache; when
they no longer match it, the cached kernels (``*.nbi`` index and ``*.nbc`` data files) are deleted
and the stamp rewritten, under a file lock, so that worker processes importing at once do it once.
A module no kernel module imports (the figures, the command line, the analyses without kernels)
cannot change a kernel's machine code, so an edit there keeps the cache.

Which cache: numba caches a function in the first of its locators (``numba.core.caching``) whose
directory it can write: with NUMBA_CACHE_DIR set, the directory it names after the source's
directory (UserProvidedCacheLocator), else the source's ``__pycache__`` (InTreeCacheLocator).
When that one cannot be written, numba falls back to a user-wide directory (UserWideCacheLocator;
ZipCacheLocator uses it too) where no stamp of glamas would keep it fresh; IPythonCacheLocator is
for functions typed into a notebook, not the package's. So on import (:func:`prepare_kernel_cache`)
glamas refreshes the directory numba chooses first, and where it cannot write that directory (or
take its lock in time, or NUMBA_CACHE_LOCATOR_CLASSES changes numba's choice), it turns numba's
caching off for the process, with one warning line: kernels then compile in every process, but
never come from a stale cache, and numba never falls back.
"""

import ast
import hashlib
import os
import re
import sys
import tempfile
from pathlib import Path

from numba.core import config as numba_config

from glamas import atomic, errors

PACKAGE = Path(os.path.abspath(os.path.dirname(__file__)))  # as numba names the cached files' sources
STAMP_NAME = "glamas-sources.sha256"
_LOCK_NAME = "glamas-sources.lock"
_CACHE_SUFFIXES = (".nbi", ".nbc")
CACHE_OFF_VARIABLE = "GLAMAS_KERNEL_CACHE_OFF"
"""Set in the environment by the process that turned caching off and said so: its worker
processes, which inherit the environment and decide the same, do not say it again."""


def source_files(package: Path = PACKAGE) -> list[Path]:
    """The package's Python sources, in a fixed order."""
    return sorted(package.rglob("*.py"))


_NUMBA = re.compile(r"^[ \t]*(?:from|import)[ \t]+numba\b", re.M)
_IMPORT = re.compile(r"^[ \t]*(?:from[ \t]+(\w+(?:\.\w+)*)[ \t]+import[ \t]+(?:\(([^)]*)\)|([^\n#]*))"
                     r"|import[ \t]+(\w+(?:\.\w+)*))", re.M)


def kernel_source_files(package: Path = PACKAGE) -> list[Path]:
    """The sources a compiled kernel can depend on, in a fixed order: every module of the package
    that imports numba, and every module of the package those import, directly or not (read
    from their import statements; a package's ``__init__`` stands for the package)."""
    files = source_files(package)
    return import_closure([path for path in files if _NUMBA.search(_text(path))], package)


def _text(path: Path) -> str:
    return path.read_text(encoding="utf-8", errors="replace")


def import_closure(start: list, package: Path | None = None, follow=None) -> list[Path]:
    """The modules ``start`` (paths of the package's sources) and every module of the package they
    import, directly or not, in a fixed order (``package``: PACKAGE, as it is when called); with
    ``follow(path) -> bool``, only the modules it accepts are reached and looked into."""
    package = PACKAGE if package is None else package
    files = source_files(package)
    texts = {path: _text(path) for path in files}
    by_name = {}
    for path in files:
        parts = (package.name,) + path.relative_to(package).with_suffix("").parts
        by_name[".".join(parts[:-1] if parts[-1] == "__init__" else parts)] = path
    reached = list(start)
    seen = set(reached)
    while reached:
        for module, names, line, plain in _IMPORT.findall(texts[reached.pop()]):
            candidates = [plain] if plain else [module] + [f"{module}.{name.split()[0]}"
                                                           for name in (names or line).split(",") if name.strip()]
            for path in (by_name.get(name) for name in candidates):
                if path is not None and path not in seen and (follow is None or follow(path)):
                    seen.add(path)
                    reached.append(path)
    return sorted(seen)


CODE_FORM = "ast-named-fields-1"
"""The name of :func:`code_digest`'s form, recorded with every record of code
(:mod:`glamas.provenance`): a record made in another form is re-recorded, not taken for changed code."""


def code_digest(path: Path) -> str:
    """A digest of what the module at ``path`` does: the SHA-256 of :func:`canonical_form` of its
    syntax tree, first 16 hex digits. The same on every supported Python."""
    stat = path.stat()
    key = (path, stat.st_mtime_ns, stat.st_size)
    if key not in _DIGESTS:
        _DIGESTS[key] = hashlib.sha256(canonical_form(_text(path)).encode()).hexdigest()[:16]
    return _DIGESTS[key]


def canonical_form(source: str) -> str:
    """The syntax tree of ``source`` without its docstrings (so comments, docstrings, blank lines and
    line breaks do not count), written as nested ``Node(field=value, ...)`` with only the fields that
    hold something. ``ast.dump`` is not used: its text changes with the Python version (3.12 gave
    functions and classes an empty ``type_params``; 3.13 leaves empty fields out), which would make
    every record of code look changed on another Python."""
    tree = ast.parse(source)
    for node in ast.walk(tree):  # docstrings, of modules, classes, functions and attributes
        body = getattr(node, "body", None)
        if isinstance(body, list):
            node.body = [statement for statement in body if not _is_text(statement)] or [ast.Pass()]
    return _written(tree)


def _written(value) -> str:
    """``value`` (a node, a list of them, or a constant) in the canonical form."""
    if isinstance(value, ast.JoinedStr):
        value = ast.JoinedStr(values=_joined_text(value.values))
    if isinstance(value, ast.AST):
        shown = ", ".join(f"{name}={_written(field)}" for name, field in ast.iter_fields(value)
                          if field is not None and field != [])
        return f"{type(value).__name__}({shown})"
    if isinstance(value, list):
        return "[" + ", ".join(_written(item) for item in value) + "]"
    return repr(value)


def _joined_text(values: list) -> list:
    """An f-string's parts with adjacent texts joined and empty texts left out, as Python 3.11
    parses them (3.12 can end a nested format spec with an empty text)."""
    joined = []
    for value in values:
        if isinstance(value, ast.Constant) and isinstance(value.value, str):
            if joined and isinstance(joined[-1], ast.Constant) and isinstance(joined[-1].value, str):
                joined[-1] = ast.Constant(value=joined[-1].value + value.value)
                continue
            if not value.value:
                continue
        joined.append(value)
    return joined


def _is_text(statement) -> bool:
    """Whether ``statement`` is a string alone: a docstring, which does nothing."""
    return isinstance(statement, ast.Expr) and isinstance(statement.value, ast.Constant) \
        and isinstance(statement.value.value, str)


_DIGESTS: dict = {}
"""code_digest by (path, modification time, size): computed once per process for a file as it is."""


def source_hash(package: Path = PACKAGE) -> str:
    """SHA-256 over the kernel sources (:func:`kernel_source_files`: relative paths and contents):
    it changes with any edit that can change a kernel."""
    digest = hashlib.sha256()
    for path in kernel_source_files(package):
        digest.update(path.relative_to(package).as_posix().encode())
        digest.update(b"\0")
        digest.update(path.read_bytes())
        digest.update(b"\0")
    return digest.hexdigest()


def prepare_kernel_cache(package: Path = PACKAGE) -> bool:
    """What glamas does on import, before any kernel is loaded: :func:`refresh_kernel_cache`, or,
    where it cannot, numba's caching turned off for this process (:func:`turn_caching_off`).
    Returns whether the cache is on."""
    try:
        refresh_kernel_cache(package)
    except (OSError, errors.UserError) as error:
        turn_caching_off(errors.one_line(error))
        return False
    return True


def refresh_kernel_cache(package: Path = PACKAGE) -> bool:
    """Delete numba's cached kernels of ``package`` if its sources changed since the stamp was
    written; returns whether it did. Raises OSError where numba's first choice of a cache cannot be
    written, :class:`glamas.atomic.LockTimeoutError` when another process holds the lock too long,
    and UserError when NUMBA_CACHE_LOCATOR_CLASSES makes numba's choice unknown."""
    locators = _numba_config().CACHE_LOCATOR_CLASSES
    if locators:
        raise errors.UserError(f"NUMBA_CACHE_LOCATOR_CLASSES={locators} chooses where numba caches, which "
                               "glamas cannot keep in step with its sources")
    for directory in cache_directories(package):
        ensure_writable(directory)
    home = cache_directory(package)
    lock = os.open(home / _LOCK_NAME, os.O_RDWR | os.O_CREAT, 0o666)
    try:
        # one importer checks and deletes; the others then find the new stamp
        atomic.wait_for_lock(lock, f"glamas's kernel cache in {home}")
        return _refresh_locked(package, home / STAMP_NAME)
    finally:
        os.close(lock)  # releases the lock


def _refresh_locked(package: Path, stamp: Path) -> bool:
    current = source_hash(package)
    try:
        if stamp.read_text() == current:
            return False
    except OSError:
        pass  # no stamp yet: whatever is cached may predate it
    for path in cached_kernels(package):
        path.unlink(missing_ok=True)
    tmp = stamp.with_name(f"{stamp.name}.{os.getpid()}.tmp")
    tmp.write_text(current)
    os.replace(tmp, stamp)
    return True


def ensure_writable(directory: Path) -> None:
    """Create ``directory`` and write a file there, as numba does before it chooses a cache
    directory (``_CacheLocator.ensure_cache_path``); OSError where numba would fall back."""
    directory.mkdir(parents=True, exist_ok=True)
    tempfile.TemporaryFile(dir=directory).close()


def turn_caching_off(reason: str) -> None:
    """Make numba's ``cache=True`` a no-op in this process (the functions decorated from now on
    compile in memory only), and say so on stderr once per run (:data:`CACHE_OFF_VARIABLE`)."""
    from numba.core.dispatcher import Dispatcher

    Dispatcher.enable_caching = _no_caching
    if os.environ.get(CACHE_OFF_VARIABLE) is None:
        print(f"warning: numba's kernel cache is off for this run, so kernels compile in every process: glamas "
              f"cannot keep it in step with its sources ({reason}); set NUMBA_CACHE_DIR to a directory you can "
              "write to", file=sys.stderr)
        os.environ[CACHE_OFF_VARIABLE] = "1"


def _no_caching(dispatcher) -> None:
    """numba's ``Dispatcher.enable_caching`` when caching is off: the dispatcher keeps its NullCache."""


def uncached(kernel) -> bool:
    """Whether calling the numba dispatcher ``kernel`` compiles it: it is compiled neither in this
    process nor in numba's cache for its source as it is (the cache's index as numba reads it, which
    is empty when the source changed since). False when caching is off: a kernel then compiles in
    every process, which :func:`turn_caching_off` said; and for a function numba does not compile."""
    index = getattr(getattr(kernel, "_cache", None), "_cache_file", None)  # a NullCache has none
    return index is not None and not kernel.overloads and not index._load_index()


def cache_directory(directory: Path) -> Path:
    """Where numba first chooses to cache the kernels of the sources in ``directory``: its
    ``__pycache__``, or under NUMBA_CACHE_DIR the subdirectory numba names after the directory and
    its path's SHA-1."""
    root = _numba_config().CACHE_DIR
    if not root:
        return directory / "__pycache__"
    return Path(root) / f"{directory.name}_{hashlib.sha1(str(directory).encode()).hexdigest()}"


def cache_directories(package: Path = PACKAGE) -> list[Path]:
    """:func:`cache_directory` of every directory of the package's sources."""
    return sorted(cache_directory(directory) for directory in {path.parent for path in source_files(package)})


def _numba_config():
    """numba's configuration as its compiler sees it: re-read from the environment (and
    .numba_config.yaml) first, as the compiler does before each compilation."""
    numba_config.reload_config()
    return numba_config


def cached_kernels(package: Path = PACKAGE) -> list[Path]:
    """numba's cache files (index and data) of the package's sources."""
    return [path for directory in cache_directories(package) if directory.is_dir() for path in directory.iterdir()
            if path.suffix in _CACHE_SUFFIXES]
