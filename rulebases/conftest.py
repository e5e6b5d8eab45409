"""`pytest rulebases/` runs the verify blocks of the shipped rule bases: one test per property."""
from fuzzyc.verify.pytest_plugin import collect_fz


def pytest_collect_file(file_path, parent):
    return collect_fz(file_path, parent)
