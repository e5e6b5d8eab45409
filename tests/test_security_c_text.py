"""No user text reaches a generated C header unescaped, in every back end and numeric mode
(float, double, q15, q31, lookup table).

A model carries hostile text in every place user text can be (controller name, title, source
path, notes, units, input/output/chain-output/term names); each header must build with the
project's strict gcc flags and leave the text inert: after the preprocessor (comments gone,
#defines kept) no token `injected` is left, and a probe that calls `injected()` fails to
link.  The reported case (a FIS output name, `fuzzyc compile --numeric q15|q31`) goes through
the CLI.  Independently of gcc, `c_guard.checked_header` (the gate every header passes) must
refuse a header whose back end forgot to escape, and the back ends' f-strings must not
interpolate a name without `c_comment` or `c_identifier`.
"""
from __future__ import annotations

import ast
import copy
import re
import shutil
import subprocess

import pytest
import sympy

from conftest import ROOT
from fuzzyc.api import compile_c, compile_lut
from fuzzyc.backends import lut as c_lut
from fuzzyc.backends.c import header as c_float
from fuzzyc.backends.c_fixed import header as c_fixed
from fuzzyc.backends.c.guard import checked_header
from fuzzyc.backends.c.load import STRICT_FLAGS
from fuzzyc.cli import main as cli_main
from fuzzyc.errors import FuzzycError
from fuzzyc.escape import c_comment
from fuzzyc.formats import load_any
from hostile_fis import sugeno_fis

needs_gcc = pytest.mark.skipif(shutil.which("gcc") is None,
                               reason="needs gcc to build the headers and the link probe")

MODES = ("float", "double", "q15", "q31", "lut")
CODE = "static inline int injected(void) { return 42; }"
# Each one tries to end the comment it is written into and define `injected`.
PAYLOADS = {
    "terminator": f"y */ {CODE} /* z",
    "line comment, newline": f"y // z\n*/ {CODE} /*\n",
    "CR, #define": f"y\r\n#define injected 42\r\n*/ {CODE} /*",
    "line splice": f"y *\\\n/ {CODE} /\\\n* z",
    "trigraph": f"y *??/\n/ {CODE} /??/\n* z",
    "NUL, control characters": f"y\x00\x01\x1b[31m\x7f\t\x0b\x0c */ {CODE} /* z",
    "quotes": f"y \" ' */ {CODE} /* \"' z",
    "non-ASCII, U+2028": f"\u00b5 \u540d \u2028 */ {CODE} /* \u2029\x85 z",
}


MAMDANI = """[System]
Name='m'
Type='mamdani'
NumInputs=1
NumOutputs=1
NumRules=2
AndMethod='min'
OrMethod='max'
ImpMethod='min'
AggMethod='max'
DefuzzMethod='centroid'

[Input1]
Name='x'
Range=[0 1]
NumMFs=2
MF1='lo':'gaussmf',[0.3 0]
MF2='hi':'gaussmf',[0.3 1]

[Output1]
Name='y'
Range=[0 10]
NumMFs=2
MF1='small':'trimf',[-5 0 5]
MF2='big':'trimf',[5 10 15]

[Rules]
1, 1 (1) : 1
2, 2 (1) : 1
"""


def base_model(tmp_path, kind: str = "sugeno"):
    """One input x (terms lo, hi), one output y (small, big), chain output y_out: Sugeno over
    a partition (every back end), or Mamdani over gaussians (float and lut: the dense path,
    which writes the term names)."""
    path = tmp_path / f"{kind}.fis"
    path.write_text(MAMDANI if kind == "mamdani" else
                    sugeno_fis("m", [("x", "lo", "hi")], ("y", "small", "big")))
    return load_any(path)


def hostile(model, payload: str):
    """A copy of the one-input FIS model with `payload` in every place user text can be."""
    m = copy.deepcopy(model)
    rb = m.rulebase
    m.name = "ctl " + payload
    m.title = "title " + payload
    m.source_path = f"/tmp/{payload}/m.fis"
    m.notes = ["note " + payload]
    m.signals[0].name = rb.inputs[0].name = "in " + payload
    rb.outputs[0].name = "out " + payload
    m.outputs[0].name = "chain " + payload
    m.outputs[0].expr = sympy.Symbol(rb.outputs[0].name)
    rb.inputs[0].names[0] = "term " + payload
    rb.outputs[0].names[1] = "oterm " + payload
    for item in (m.signals[0], m.outputs[0], rb.inputs[0], rb.outputs[0]):
        item.unit = "unit " + payload
    return m


def header_of(model, mode: str):
    return compile_lut(model, 5) if mode == "lut" else compile_c(model, mode)


def run(cmd, cwd):
    return subprocess.run(cmd, capture_output=True, text=True, cwd=cwd)


def injection_found(text: str, tmp_path) -> list[str]:
    """What gcc shows of `injected` in a header that builds strictly: [] when it is inert."""
    (tmp_path / "h.h").write_text(text)
    built = run(["gcc", *STRICT_FLAGS, "-x", "c", "-c", "h.h", "-o", "h.o"], tmp_path)
    assert built.returncode == 0, built.stderr
    found = []
    code = run(["gcc", "-std=c99", "-E", "-P", "-dD", "-x", "c", "h.h"], tmp_path)
    assert code.returncode == 0, code.stderr
    found += [line for line in code.stdout.splitlines() if re.search(r"\binjected\b", line)]
    (tmp_path / "probe.c").write_text('#include "h.h"\nint injected(void);\n'
                                      "int main(void) { return injected(); }\n")
    probe = run(["gcc", "-std=c99", "probe.c", "-o", "probe"], tmp_path)
    if probe.returncode == 0:
        found.append("the probe calling injected() linked")
    else:
        assert "undefined reference to `injected'" in probe.stderr, probe.stderr
    return found


@needs_gcc
def test_the_checks_see_a_live_injection(tmp_path):
    # the oracle: a header whose comment was closed by the name defines injected()
    live = f"/* y */ {CODE} /* z */\n"
    found = injection_found(live, tmp_path)
    assert any("injected(void)" in f for f in found)
    assert "the probe calling injected() linked" in found
    assert injection_found("/* y * / static int injected = 1; / * z */\ntypedef int t;\n",
                           tmp_path) == []


# the texts each header shows (in comments), by its prefix in `hostile`, beside the path
SHOWN = {("sugeno", "float"): ("title", "in", "chain"),
         ("sugeno", "double"): ("title", "in", "chain"),
         ("sugeno", "q15"): ("in", "out", "chain"), ("sugeno", "q31"): ("in", "out", "chain"),
         ("sugeno", "lut"): ("in", "out"),
         ("mamdani", "float"): ("title", "in", "chain", "term"),
         ("mamdani", "double"): ("title", "in", "chain", "term"), ("mamdani", "lut"): ("in", "out")}


@needs_gcc
@pytest.mark.parametrize("base, mode", SHOWN)
@pytest.mark.parametrize("kind", PAYLOADS)
def test_hostile_text_everywhere_is_inert(tmp_path, kind, base, mode):
    payload = PAYLOADS[kind]
    model = hostile(base_model(tmp_path, base), payload)
    header = header_of(model, mode)
    assert re.fullmatch(r"ctl_\w*\.h", header.filename, re.ASCII)   # [A-Za-z0-9_] only
    assert injection_found(header.text, tmp_path) == []
    # the text arrived, shown escaped
    for prefix in SHOWN[base, mode]:
        assert c_comment(f"{prefix} {payload}") in header.text
    assert c_comment(f"/tmp/{payload}/m.fis") in header.text


REPORTED = f"y */ {CODE} /*"


@needs_gcc
@pytest.mark.parametrize("options", [["--numeric", "q15"], ["--numeric", "q31"],
                                     ["--numeric", "float"], ["--numeric", "double"],
                                     ["--target", "lut", "--resolution", "5"]])
def test_the_reported_fis_output_name_through_the_cli(tmp_path, capsys, options):
    path = tmp_path / "f.fis"
    path.write_text(sugeno_fis("m", [("x", "lo", "hi")], (REPORTED, "small", "big")))
    out = tmp_path / "out"
    out.mkdir()
    assert cli_main(["compile", str(path), *options, "-o", str(out)]) == 0
    [written] = out.glob("*.h")
    text = written.read_text()
    assert c_comment(REPORTED) in text and REPORTED not in text
    assert injection_found(text, tmp_path) == []


# -- the gate: a back end that forgot to escape is refused, not written ------------------------

@pytest.mark.parametrize("module, modes", [(c_float, ("float", "double")),
                                           (c_fixed, ("q15", "q31")), (c_lut, ("lut",))])
@pytest.mark.parametrize("payload, says", [
    ("y */ int injected = 5; /* z", "cannot be written into the C header"),
    ("y\n*/ int injected = 5; /* z", "cannot be written into the C header"),
    ("y \u2028 \x00 z", "internal error"),
])
def test_a_forgotten_escape_is_refused(tmp_path, monkeypatch, module, modes, payload, says):
    model = hostile(base_model(tmp_path), payload)
    monkeypatch.setattr(module, "c_comment", lambda text: text)    # the bug: no escaping
    for mode in modes:
        with pytest.raises(FuzzycError, match=says):
            header_of(model, mode)


def test_the_q15_derived_sentence_of_the_report_is_escaped(tmp_path, monkeypatch):
    model = hostile(base_model(tmp_path), PAYLOADS["terminator"])
    writer = c_fixed.FixedPointWriter(model, "q15")
    assert "derived" not in writer.derived_text()      # the bound is derived: names are shown
    assert c_comment("out " + PAYLOADS["terminator"]) in writer.derived_text()
    # the sentence as it was: the gate refuses the header
    monkeypatch.setattr(c_fixed.FixedPointWriter, "derived_text", lambda self: "; ".join(
        f"{v.name} 0.001" for v in self.rb.outputs))
    with pytest.raises(FuzzycError, match="the variable name 'out y \\*/"):
        c_fixed.generate_fixed_header(model, "q15")


@pytest.mark.parametrize("header, says", [
    ("/* a */\nint x;\n", None),
    ("/* a\nint x;\n", "leaves a comment open"),
    ("/* a */ b */\nint x;\n", "`\\*/` outside a comment"),
    ("/* a /* b */\n", "nests `/\\*`"),
    ("int x; // c\n", "`//` outside a comment"),
    ('static const char *s = "a";\n', "`\"` outside a comment"),
    ("/* a \\\n*/ int x;\n", "holds `\\\\`"),
    ("/* a ??/\n*/ int x;\n", "holds `\\?\\?`"),
    ("/* a\r */\n", "holds '\\\\r'"),
    ("/* \u2028 */\n", "holds '\\\\u2028'"),
    ("/* \x00 */\n", "holds '\\\\x00'"),
])
def test_the_gate_reads_the_header_as_the_compiler_does(tmp_path, header, says):
    model = base_model(tmp_path)
    if says is None:
        assert checked_header(header, model) is header
    else:
        with pytest.raises(FuzzycError, match="internal error.*" + says):
            checked_header(header, model)


def test_a_delimiter_made_at_the_edge_of_an_unescaped_text_is_refused(tmp_path):
    # a call site that wrote "/ int x; /" verbatim between the header's `*`s: the text holds
    # no delimiter, but its first and last characters close and reopen a comment with the `*`
    # beside them; the code between, ` int x; `, passes rules 1-3 and only rule 4 sees it
    model = base_model(tmp_path)
    model.title = "/ int x; /"
    header = "/* title *" + model.title + "* end */\n"
    with pytest.raises(FuzzycError, match="the title '/ int x; /' cannot be written"):
        checked_header(header, model)


@pytest.mark.parametrize("mode", MODES)
def test_a_text_made_of_a_delimiter_is_refused_with_a_message(tmp_path, mode):
    # `*/` alone cannot be told from the header's own comment ends: refused, never written
    model = base_model(tmp_path)
    model.title = "*/"
    with pytest.raises(FuzzycError, match=r"the title '\*/' cannot be written into the C "
                                          r"header.*rename it"):
        header_of(model, mode)


def test_cli_refuses_a_delimiter_title_without_a_traceback(tmp_path, capsys):
    path = tmp_path / "d.fll"
    path.write_text((ROOT / "tests" / "format_corpus" / "coa.fll").read_text()
                    .replace("Engine: coa", "Engine: coa\ndescription: */", 1))
    assert load_any(path).title == "*/"
    assert cli_main(["compile", str(path), "-o", str(tmp_path)]) == 2
    err = capsys.readouterr().err
    assert "error: the title '*/' cannot be written into the C header" in err
    assert "Traceback" not in err and not list(tmp_path.glob("*.h"))


def test_shipped_headers_pass_the_gate_unchanged():
    model = load_any(ROOT / "rulebases" / "wedm_corner.fz")
    for mode in ("float", "q15", "q31"):
        try:
            text = header_of(model, mode).text
        except FuzzycError:
            continue            # a rule base the fixed-point back end does not emit
        assert checked_header(text, model) is text


# -- the call sites: names reach f-strings only through c_comment or c_identifier ---------------

USER_ATTRS = {"name", "names", "title", "source_path", "unit", "notes", "text", "origins"}
# HeaderWriter.symbol spells a name as v_ or PARAM_ + c_identifier
ESCAPES = {"c_comment", "c_identifier", "symbol"}
# the diagnostics (FuzzycError messages: the terminal, not a file)
NOT_A_FILE = {"_fail", "FuzzycError", "Diagnostic"}
# the header's identifier prefix (c_identifier of the model's name), the C type's name and the
# file name in a Frama-C alarm (a report line)
SAFE_ATTRS = {"self.name", "self.real.name", "real.name", "Path(where).name"}
# writes no C: the gate's own messages name the texts it refuses
NOT_A_WRITER = {"c_guard.py"}


def _called(node) -> str:
    f = node.func
    return f.id if isinstance(f, ast.Name) else f.attr if isinstance(f, ast.Attribute) else ""


def unescaped_interpolations(source: str) -> list[str]:
    """`line: expression` for each f-string value that reads a user-text attribute outside
    c_comment/c_identifier, except in diagnostics and enum names (`X.name.lower()`)."""
    found = []

    def visit(node, escaped: bool, diagnostic: bool, in_fstring: bool):
        if isinstance(node, ast.Call):
            escaped = escaped or _called(node) in ESCAPES
            diagnostic = diagnostic or _called(node) in NOT_A_FILE
        if isinstance(node, ast.Assign) and any(ast.unparse(t) == "self.where"
                                                for t in node.targets):
            diagnostic = True              # the fixed chain's context for its diagnostics
        in_fstring = in_fstring or isinstance(node, ast.FormattedValue)
        if isinstance(node, ast.Attribute) and node.attr in USER_ATTRS and in_fstring and \
                not escaped and not diagnostic and ast.unparse(node) not in SAFE_ATTRS:
            found.append(f"{node.lineno}: {ast.unparse(node)}")
        children = list(ast.iter_child_nodes(node))
        if isinstance(node, ast.Subscript):      # a name as a key (`errors[o.name]`) is not shown
            visit(node.slice, escaped, diagnostic, False)
            children = [node.value]
        if isinstance(node, ast.Attribute) and node.attr == "lower" and \
                isinstance(node.value, ast.Attribute) and node.value.attr == "name":
            children = [node.value.value]      # an enum's name, lower-cased
        for child in children:
            visit(child, escaped, diagnostic, in_fstring)

    visit(ast.parse(source), False, False, False)
    return found


def test_the_scan_finds_an_unescaped_name():
    assert unescaped_interpolations('x = f"/* {v.name} */"') == ['1: v.name']
    assert unescaped_interpolations('x = f"/* {c_comment(v.name)} */"') == []
    assert unescaped_interpolations('raise _fail(f"`{v.name}` is bad")') == []
    assert unescaped_interpolations('x = f"{e[o.name]:.3g} {v.title}"') == ['1: v.title']
    assert unescaped_interpolations('x = f"{p.unit.lower()}"') == ['1: p.unit']


def test_no_back_end_interpolates_a_name_unescaped():
    found = {path.name: unescaped_interpolations(path.read_text())
             for path in sorted((ROOT / "fuzzyc" / "backends").glob("*.py"))
             if path.name not in NOT_A_WRITER}
    assert {k: v for k, v in found.items() if v} == {}
