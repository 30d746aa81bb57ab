"""The kernels' on-disk cache follows their sources (sim/kernel_cache.py), and every module with
kernels is listed where set-up compiles them (the Makefile's KERNELS)."""
import re
from pathlib import Path

from sim.kernel_cache import KERNEL_MODULES, ROOT, drop_stale_caches


def test_every_module_with_kernels_is_listed_here_and_in_the_makefile():
    with_kernels = {str(p.relative_to(ROOT)) for p in ROOT.rglob("*.py") if re.search(r"^@njit", p.read_text(), re.M)}
    assert with_kernels == set(KERNEL_MODULES)
    makefile = (ROOT.parent / "Makefile").read_text()
    listed = re.search(r"KERNELS := \$\(addprefix sim/,(.*?)\)\n", makefile, re.S).group(1)
    assert set(listed.replace("\\", " ").split()) == set(KERNEL_MODULES)


def test_a_changed_source_drops_every_cache(tmp_path: Path):
    (tmp_path / "a.py").write_text("x = 1\n")
    cache = tmp_path / "sub" / "__pycache__"
    cache.mkdir(parents=True)
    (cache / "b.f-1.py311.nbi").write_text("index")
    assert drop_stale_caches(tmp_path, ("a.py",))  # no stamp yet: built from unknown sources
    assert not (cache / "b.f-1.py311.nbi").exists()
    (cache / "b.f-1.py311.nbi").write_text("index")
    assert not drop_stale_caches(tmp_path, ("a.py",))  # the same sources: kept
    assert (cache / "b.f-1.py311.nbi").exists()
    (tmp_path / "a.py").write_text("x = 2\n")
    assert drop_stale_caches(tmp_path, ("a.py",))
    assert not (cache / "b.f-1.py311.nbi").exists()
