"""`pytest rulebases/` runs the verify blocks of the shipped rule bases, one test per property:
the fuzzyc pytest plugin (entry point) collects them, enabled by `fuzzyc_verify = true` in
pyproject.toml. Closed-loop properties need fuzzyc.plants, aliased here in a source tree."""
import importlib.util
import pathlib

try:
    import fuzzyc.plants  # noqa: F401  (installed: runtime/ and plants/ live under fuzzyc)
except ImportError:       # source tree run on its own: reuse the suite's aliasing
    _spec = importlib.util.spec_from_file_location(
        "_fuzzyc_source_aliases", pathlib.Path(__file__).resolve().parents[1] / "tests" / "conftest.py")
    _spec.loader.exec_module(importlib.util.module_from_spec(_spec))
