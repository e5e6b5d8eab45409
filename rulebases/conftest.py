"""`pytest rulebases/` runs the verify blocks of the shipped rule bases: one test per property."""
import importlib.util
import pathlib

try:
    import fuzzyc.plants  # noqa: F401  (installed: runtime/ and plants/ live under fuzzyc)
except ImportError:       # source tree run on its own: reuse the suite's aliasing
    _spec = importlib.util.spec_from_file_location(
        "_fuzzyc_source_aliases", pathlib.Path(__file__).resolve().parents[1] / "tests" / "conftest.py")
    _spec.loader.exec_module(importlib.util.module_from_spec(_spec))

from fuzzyc.verify.pytest_plugin import collect_fz  # noqa: E402


def pytest_collect_file(file_path, parent):
    return collect_fz(file_path, parent)
