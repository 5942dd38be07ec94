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


def test_ready_markers_name_sources_and_target_and_go_with_stale_caches(
    tmp_path: Path, monkeypatch: pytest.MonkeyPatch
) -> None:
    monkeypatch.setattr(_jit_cache, "_PACKAGE", tmp_path)
    monkeypatch.delenv("NUMBA_CACHE_DIR", raising=False)
    _layout(tmp_path)
    monkeypatch.setattr(_jit_cache, "_checked", False)
    _jit_cache.ensure_fresh()
    assert not _jit_cache.is_marked("eof-ga", "cpu1")
    _jit_cache.mark("eof-ga", "cpu1")
    assert _jit_cache.is_marked("eof-ga", "cpu1")
    assert not _jit_cache.is_marked("eof-ga", "cpu2")  # another code-generation target
    assert not _jit_cache.is_marked("eof-lm", "cpu1")
    (tmp_path / _jit_cache.COMPILED[1]).write_text("# edited\n")  # the sources change
    assert not _jit_cache.is_marked("eof-ga", "cpu1")
    monkeypatch.setattr(_jit_cache, "_checked", False)
    _jit_cache.ensure_fresh()
    assert not list((tmp_path / "__pycache__").glob("hapticsim-ready-*"))
    monkeypatch.setenv("NUMBA_CACHE_DIR", str(tmp_path / "elsewhere"))  # numba's own choice
    _jit_cache.mark("eof-lm", "cpu1")
    assert list((tmp_path / "elsewhere").glob("hapticsim-ready-eof-lm-*"))
