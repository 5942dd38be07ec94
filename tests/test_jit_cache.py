"""The numba cache of the compiled kernels is dropped when any of their sources changes."""

from __future__ import annotations

from pathlib import Path

import pytest

from hapticsim import _jit_cache


def _layout(root: Path) -> list[Path]:
    cached = []
    for name in _jit_cache.COMPILED:
        module = root / name
        module.parent.mkdir(parents=True, exist_ok=True)
        module.write_text(f"# {name}\n")
        pycache = module.parent / "__pycache__"
        pycache.mkdir(exist_ok=True)
        for suffix in ("nbi", "nbc"):
            path = pycache / f"{module.stem}.kernel-12.py311.{suffix}"
            path.write_bytes(b"x")
            cached.append(path)
    return cached


def test_cache_files_go_when_a_source_changes(tmp_path: Path, monkeypatch: pytest.MonkeyPatch):
    monkeypatch.setattr(_jit_cache, "_PACKAGE", tmp_path)
    other = tmp_path / "geometry" / "__pycache__" / "superquadric.cpython-311.pyc"

    def check() -> None:
        monkeypatch.setattr(_jit_cache, "_checked", False)
        _jit_cache.ensure_fresh()

    cached = _layout(tmp_path)
    other.write_bytes(b"keep")
    check()  # no fingerprint yet: caches of unknown age go
    assert not any(p.exists() for p in cached)
    cached = _layout(tmp_path)
    check()  # same sources: the caches stay
    assert all(p.exists() for p in cached)
    (tmp_path / _jit_cache.COMPILED[0]).write_text("# edited\n")  # the kernel changes
    check()
    assert not any(p.exists() for p in cached) and other.exists()


def test_the_list_names_every_module_with_cached_kernels() -> None:
    package = Path(_jit_cache.__file__).parent
    cached = {
        str(p.relative_to(package)) for p in package.rglob("*.py") if "cache" in p.read_text()
        and "njit" in p.read_text()
    }  # fmt: skip
    assert cached <= set(_jit_cache.COMPILED), f"add {sorted(cached - set(_jit_cache.COMPILED))}"


class _Terminal:
    def __init__(self, tty: bool) -> None:
        self.tty, self.text = tty, ""

    def isatty(self) -> bool:
        return self.tty

    def write(self, text: str) -> None:
        self.text += text

    def flush(self) -> None:
        pass


def test_a_cold_cache_is_announced_on_a_terminal_only(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(_jit_cache, "_PACKAGE", tmp_path)
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    (tmp_path / "geometry" / "__pycache__").mkdir(parents=True)
    terminal, pipe = _Terminal(True), _Terminal(False)
    assert _jit_cache.is_cold()
    assert _jit_cache.note_if_cold(terminal) and "compiling" in terminal.text
    assert not _jit_cache.note_if_cold(pipe) and pipe.text == ""  # scripts and tests: silent
    index = tmp_path / "geometry" / "__pycache__" / "_eof_compiled.kernel-1.py311.nbi"
    index.write_bytes(b"x")
    assert not _jit_cache.is_cold() and not _jit_cache.note_if_cold(_Terminal(True))
    index.unlink()
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "elsewhere"))  # cannot tell: silent
    assert not _jit_cache.is_cold()
