"""Package discovery under the package-dir mapping (the rest of the metadata is pyproject.toml).

runtime/ and plants/ (and the data folders rulebases/, examples/) stay at the repository root
because they show the architecture, but install under the fuzzyc namespace, so nothing generic
like `runtime` lands in site-packages. setuptools' automatic discovery does not rename packages,
so each root is searched here and its subpackages are named under its installed name: a new
subpackage or data folder is found without being listed (tests/test_wheel_contents.py checks
that every file of these folders reaches the wheel).
"""
from setuptools import find_namespace_packages, setup

ROOTS = {"fuzzyc": "fuzzyc", "fuzzyc.runtime": "runtime", "fuzzyc.plants": "plants",
         "fuzzyc.rulebases": "rulebases", "fuzzyc.examples": "examples"}


def packages_under(name: str, folder: str) -> list[str]:
    found = find_namespace_packages(folder, exclude=["*__pycache__*"])
    return [name] + [f"{name}.{sub}" for sub in found if f"{name}.{sub}" not in ROOTS]


setup(package_dir=ROOTS,
      packages=[p for name, folder in ROOTS.items() for p in packages_under(name, folder)])
