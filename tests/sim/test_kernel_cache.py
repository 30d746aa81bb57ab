"""The kernels' on-disk cache follows their sources (sim/kernel_cache.py)."""

from pathlib import Path

from sim.kernel_cache import drop_stale_caches


def test_a_changed_source_drops_every_cache(tmp_path: Path):
    (tmp_path / "a.py").write_text("x = 1\n")
    cache = tmp_path / "sub" / "__pycache__"
    cache.mkdir(parents=True)
    (cache / "b.f-1.py311.nbi").write_text("index")
    assert drop_stale_caches(tmp_path)  # no stamp yet: built from unknown sources
    assert not (cache / "b.f-1.py311.nbi").exists()
    (cache / "b.f-1.py311.nbi").write_text("index")
    assert not drop_stale_caches(tmp_path)  # the same sources: kept
    assert (cache / "b.f-1.py311.nbi").exists()
    (tmp_path / "sub" / "c.py").write_text("y = 2\n")  # any source changed (here: a new one)
    assert drop_stale_caches(tmp_path)
    assert not (cache / "b.f-1.py311.nbi").exists()
