"""The API's results show themselves (issue 30): a short repr and an escaped HTML table for the
model, the verify report and a simulation (fuzzyc/display.py)."""
from __future__ import annotations

import doctest
import html.parser

import fuzzyc
import fuzzyc.display

HEATER = """controller heater {
  input temp : degC in [0, 100]
  terms temp : cold = lshoulder(20, 60), hot = rshoulder(40, 80)
  var power in [0, 1]
  terms power : singletons low = 0 high = 1
  rule if temp is cold then power is high
  rule if temp is hot then power is low
  output heating : W in [0, 2000] = 2000 * power
  verify {
    complete
    covers temp at least 0.5
  }
}"""

HOSTILE = "<script>alert(1)</script>"


class Tags(html.parser.HTMLParser):
    """The tags and text of an HTML fragment, as a browser would read them."""

    def __init__(self) -> None:
        super().__init__()
        self.tags: list[str] = []
        self.text: list[str] = []

    def handle_starttag(self, tag, attrs) -> None:
        self.tags.append(tag)

    def handle_data(self, data) -> None:
        self.text.append(data)


def read_html(fragment: str) -> Tags:
    tags = Tags()
    tags.feed(fragment)
    return tags


def test_display_doctests():
    result = doctest.testmod(fuzzyc.display)
    assert result.attempted >= 2 and result.failed == 0


def test_model_repr_names_ranges_units_and_counts():
    model = fuzzyc.parse(HEATER, name="heater.fz")
    assert repr(model) == (
        "Model heater (heater.fz): 1 rule block, 2 rules, 2 properties\n"
        "  inputs:  temp in [0, 100] degC\n"
        "  rules:   temp (2 terms) -> power (2 terms), 2 rules\n"
        "  outputs: heating in [0, 2000] W")


def test_shipped_model_repr_is_short():
    # the dataclass dump of this model was 4,278 characters
    model = fuzzyc.load(fuzzyc.example("wedm_three_region.fz"))
    text = repr(model)
    assert len(text.splitlines()) == 4 and len(text) < 400
    assert "spark_freq in [0, 200] kHz" in text and "75 rules" in text
    assert "feed in [0, 3] mm/min" in text and "t_off in [1.6, 48] us" in text


def test_model_html_tables_variables_terms_and_rules():
    model = fuzzyc.parse(HEATER, name="heater.fz")
    page = model._repr_html_()
    tags = read_html(page)
    assert tags.tags.count("table") == 3          # variables, rules, properties
    text = "|".join(tags.text)
    # variables: raw input, the rule base's two, the output: 4 rows + header of 5 cells
    assert "raw input|temp|[0, 100]|degC" in text
    assert "rule-base input|temp|[0, 100]|degC|cold hot" in text
    assert "rule-base output|power|[0, 1]|-|low high" in text
    assert "output|heating|[0, 2000]|W" in text
    assert "1|if temp is cold then power is high|1" in text
    assert "2|if temp is hot then power is low|1" in text
    assert "covers temp at least 0.5" in text


def test_model_html_escapes_user_names():
    model = fuzzyc.parse(HEATER, name="heater.fz")
    model.name, model.title = HOSTILE, HOSTILE
    model.rulebase.inputs[0].names[0] = HOSTILE
    model.rulebase.inputs[0].unit = HOSTILE
    page = model._repr_html_()
    tags = read_html(page)
    assert "script" not in tags.tags
    # the text a browser shows still holds the name, as written
    assert sum(HOSTILE in t for t in tags.text) >= 3
    assert HOSTILE in repr(model)          # the terminal shows it verbatim


def test_report_repr_counts_verdicts_and_names_the_failure():
    report = fuzzyc.verify(fuzzyc.parse(HEATER, name="heater.fz"))
    lines = repr(report).splitlines()
    # complete is proved on the table; covers 0.5 fails between 40 and 60 (docs/api.md)
    assert lines[0] == ("VerifyReport: 2 properties: 1 proved, 0 held, 1 violated, 0 known "
                        "findings, 0 undecided; 1 failure")
    assert lines[1].startswith("  VIOLATED heater.fz::covers temp at least 0.5 [violated")
    assert len(lines) == 2
    text = "|".join(read_html(report._repr_html_()).text)
    assert "heater.fz::complete|proved|" in text
    assert "heater.fz::covers temp at least 0.5|violated|" in text


def test_report_html_escapes_and_marks_findings():
    report = fuzzyc.verify(fuzzyc.load(fuzzyc.example("wedm_three_region.fz")),
                           only="monotone du1 increasing in e2 where e1 is ZO")
    assert repr(report).endswith("1 known findings, 0 undecided; passed")
    assert "|finding|" in "|".join(read_html(report._repr_html_()).text)
    report.results[0].name = HOSTILE
    assert "script" not in read_html(report._repr_html_()).tags


def test_simulation_repr_is_short_and_holds_the_metrics():
    # two seconds at 40 ms are 50 samples; print(sim) was 27,932 characters of arrays
    sim = fuzzyc.simulate("wedm_rough", settings={"duration": 2}, batch=3)
    text = repr(sim)
    lines = text.splitlines()
    assert lines[0] == ("Simulation wedm_rough (fuzzy): 50 samples to t = 2 s, period 0.04 s, "
                        "batch 3")
    assert lines[1].startswith("  signals: feed, t_off,")
    assert "  wire ruptures = 0 count" in lines or "more metrics" in lines[-1]
    assert len(lines) <= 2 + fuzzyc.display.MAX_LINES + 1 and len(text) < 1200
    m = sim.metrics["max(spark_freq)"]
    assert f"max(spark_freq) = {m['mean']:.4g} ({m['min']:.4g} to {m['max']:.4g}) kHz" in text
    tags = read_html(sim._repr_html_())
    assert tags.tags.count("tr") == 1 + len(sim.metrics)
    sim.metrics[HOSTILE] = {"mean": 1.0, "min": 1.0, "max": 1.0, "unit": HOSTILE}
    assert "script" not in read_html(sim._repr_html_()).tags
