"""`--seed S` draws the same closed-loop cases whatever else the process has imported.

hypothesis mixes numeric literals of local modules into its draws; a module with literals
inside the drawn ranges, imported between two draws, changed the cases drawn for one seed
(the pytest worker and `fuzzyc verify` load different modules)."""
import importlib
import sys

from fuzzyc.verifier import closed_loop


class _Loop:
    duration = 300.0

    @staticmethod
    def steppable(key):
        return key == "plant.height"


ARGS = {"vary": {"plant.height": (20.0, 50.0), "plant.tension": (600.0, 1000.0)}}


def test_cases_do_not_depend_on_the_modules_loaded(tmp_path, monkeypatch):
    before = closed_loop._draw_cases(_Loop(), ARGS, 30, seed=0)
    # literals inside both ranges, in a local module loaded after the first draw
    (tmp_path / "fz_local_literals.py").write_text(
        "HEIGHTS = (23.456789, 31.13579, 47.2468)\nTENSIONS = (612.345, 777.777, 987.654)\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    importlib.import_module("fz_local_literals")
    try:
        after = closed_loop._draw_cases(_Loop(), ARGS, 30, seed=0)
    finally:
        sys.modules.pop("fz_local_literals", None)
    assert after == before
    drawn = {c["plant.height"] for c in after} | {c["plant.tension"] for c in after}
    assert not drawn & {23.456789, 31.13579, 47.2468, 612.345, 777.777, 987.654}
