"""The API's names stay the API's after every internal module is imported.

A submodule named like an API function (fuzzyc/learn.py beside fuzzyc.learn()) becomes an
attribute of the package when anything imports it, and the package's lazy __getattr__ is then
never asked: `fuzzyc.learn(...)` raised "'module' object is not callable" in the installed wheel.
"""
import importlib
import pkgutil
import types

import fuzzyc

# Modules that need an optional tool at import time are skipped, not failed.
OPTIONAL = ("fuzzyc.pytest_plugin",)


def test_api_names_resolve_to_the_api_after_importing_every_module():
    for info in pkgutil.walk_packages(fuzzyc.__path__, "fuzzyc."):
        if info.name.startswith(OPTIONAL) or info.name.endswith("__main__"):
            continue
        try:
            importlib.import_module(info.name)
        except ImportError:
            continue  # an optional dependency (gymnasium, dask) absent here
    api = importlib.import_module("fuzzyc.api")
    for name in fuzzyc.__all__:
        if name == "__version__":
            continue
        value = getattr(fuzzyc, name)
        if isinstance(value, types.ModuleType):
            # a package may share an API function's name only by being that function
            assert callable(value), f"fuzzyc.{name} is the module {value.__name__}, not the API"
        elif hasattr(api, name):
            assert value is getattr(api, name), f"fuzzyc.{name} is not fuzzyc.api.{name}"
