"""Generators: inputs built from what the grammars and schemas allow, not mutated seed files.

Mutating the project's own files rarely writes a 1,000-deep list, an alias bomb, 300 hedges or
a variable called `*/`; a hostile user writes those first. Each generator draws one integer
from hypothesis (so a run is reproducible from --seed) and builds the input with
`random.Random(that integer)`: big structures stay cheap to draw and hypothesis never runs out
of data.

- names: .fz keywords, the names the compiler itself generates, C keywords, comment
  delimiters, control characters, long and non-ASCII names;
- scenario YAML: every key of the schema (plants/scenario_schema.py, plants/registry.py) with
  values of every YAML type, anchors and aliases (alias bombs too), nesting up to 1,000 deep;
- rule bases: FLL, FCL and FIS files with terms of every shape, rules of random depth with
  and/or/not/brackets and up to hundreds of hedges, hostile names and numbers;
- command-line values: numbers spelled every way (huge, negative, non-ASCII digits, `1_000`,
  empty) for every option, `--set KEY=YAML` over the scenario keys;
- API values: what `fuzzyc.evaluate` may be given (every numpy dtype and shape, masked,
  object, datetime64, complex, huge ints, None).
"""
from __future__ import annotations

import json
import random
from fractions import Fraction
from decimal import Decimal

from hypothesis import strategies as st

# -- names -------------------------------------------------------------------------------------

C_KEYWORDS = ("int", "float", "double", "char", "void", "return", "static", "const", "struct",
              "if", "else", "while", "for", "sizeof", "typedef", "define", "include", "main",
              "NULL", "auto", "register", "volatile", "inline", "restrict", "_Bool", "int32_t",
              "uint8_t", "errno", "signed", "default", "case", "goto", "union", "enum")
# what the compiler and the converters name things themselves (a user name must not clash)
GENERATED = ("__delta1_x", "__delta2_y", "x_out", "y_out", "y_out2", "_v1", "_v", "_t", "__x",
             "x__y", "_", "__", "_1", "delta", "integrate", "clamp", "fz_state", "fuzzyc",
             "FUZZYC_H", "n_rules", "out", "in")
FORMAT_WORDS = ("Engine", "InputVariable", "OutputVariable", "RuleBlock", "term", "rule", "if",
                "then", "is", "and", "or", "not", "very", "somewhat", "any", "with", "range",
                "FUNCTION_BLOCK", "END_FUNCTION_BLOCK", "VAR_INPUT", "END_VAR", "FUZZIFY",
                "END_FUZZIFY", "TERM", "RULE", "IS", "AND", "OR", "NOT", "WITH", "RANGE",
                "System", "Name", "Input1", "Rules", "NumMFs", "MF1", "nan", "inf", "NaN")
HOSTILE_NAMES = ("*/", "/*", "//", "*/ int injected; /*", "x*/y", "??=", "??/", "\\", "a\\",
                 "\n", "a\nb", "a\rb", "a\x00b", "\x00", "\x1b[31m", "\t", "\v", "\f",
                 "\u2028", "\x85", "\ufeff", "a b", "", " ", "é", "名前", "𝔵", "ﬁ", "Ⅸ",
                 "a" * 255, "a" * 256, "a" * 261, "x" * 5000, "1x", "9", "-x", "x-y", "x.y",
                 "x::y", "'x'", '"x"', "`x`", "x`y", "x;", "x)", "(x", "x,y", "x=1", "x#y",
                 "%s%n", "${x}", "$(id)", "../x", "CON", "con.h", "x.h", "#define")


def fz_keywords() -> tuple[str, ...]:
    from fuzzyc.language.parser import keywords
    return tuple(sorted(keywords()))


def name(rnd: random.Random) -> str:
    """A name a hostile user might give a variable, a term or a model."""
    kind = rnd.random()
    if kind < 0.35:       # a plain name, so that the rest of the file gets checked too
        return rnd.choice("abcxyz") + "".join(rnd.choice("abcdefgh0123456789_")
                                             for _ in range(rnd.randint(0, 8)))
    pool = rnd.choice((fz_keywords(), C_KEYWORDS, GENERATED, FORMAT_WORDS, HOSTILE_NAMES))
    text = rnd.choice(pool)
    if rnd.random() < 0.15:
        text = rnd.choice(("", "_", "x")) + text + rnd.choice(("", "_", "1", "_out"))
    if rnd.random() < 0.05:
        text = "".join(chr(rnd.choice((rnd.randint(0, 0x7f), rnd.randint(0x80, 0x2fff))))
                       for _ in range(rnd.randint(1, 6)))
    return text


# -- numbers as text ---------------------------------------------------------------------------

HOSTILE_NUMBERS = ("nan", "NaN", "-nan", "inf", "-inf", "Infinity", "1e400", "-1e400", "1e308",
                   "1e-320", "5e-324", "1e13", "-1e13", "1e-13", "-0", "0", "0.0", "1e", ".",
                   "-", "+", "", "0x1F", "0b1", "0o7", "1_000", "1__0", "+1", ".5", "5.",
                   "9" * 400, "9" * 4301, "١", "１", "१२", "½", "1,5", "1 000", "1e+", "--1",
                   "\u22121", "1e1000000")


def number(rnd: random.Random, lo: float = 0.0, hi: float = 10.0, hostile: float = 0.08) -> str:
    """Mostly a number in [lo, hi] (so a rule base stays valid-ish), with probability
    `hostile` a hostile spelling or value."""
    if rnd.random() < hostile:
        return rnd.choice(HOSTILE_NUMBERS)
    return f"{rnd.uniform(lo, hi):.{rnd.choice((0, 1, 3, 6, 17))}f}"


def integer_spelling(rnd: random.Random, small: int) -> str:
    """An integer for an option: in range (0..small) or far past any limit, spelled as a user
    might: underscores, non-ASCII digits, a sign, spaces, float syntax, hex, or not at all."""
    value = rnd.choice((rnd.randint(0, max(small, 0)), rnd.randint(-3, 0), 99999999999, 2 ** 63,
                        2 ** 64 + 1, -2 ** 63 - 1, int("9" * 400)))
    text = str(value)
    if rnd.random() < 0.03:               # past Python's 4,300-digit limit of int(str)
        return "1" + "0" * 4300
    style = rnd.randint(0, 11)
    if style == 0 and abs(value) >= 1000:
        text = f"{value:_}"
    elif style == 1:
        text = text.translate(str.maketrans("0123456789", "٠١٢٣٤٥٦٧٨٩"))
    elif style == 2:
        text = text.translate(str.maketrans("0123456789", "０１２３４５６７８９"))
    elif style == 3:
        text = rnd.choice(("+", " ", "\t")) + text + rnd.choice(("", " ", "\n"))
    elif style == 4:
        text = f"{value}.0" if abs(value) < 1000 else f"{float(min(value, 10**300)):e}"
    elif style == 5:
        text = hex(value)
    elif style == 6:
        text = rnd.choice(HOSTILE_NUMBERS)
    return text


# -- scenario YAML -----------------------------------------------------------------------------

# what a scenario may name (plants/registry.py) and what it must not
MAKES = ("fopdt.PI", "wedm_gap.VoltageP", "edm_sink.PIGapServo", "milling.ConstantFeed",
         "wedm_corner.NoCornerControl", "filters.lowpass", "filters.bandstop",
         "filters.lowpass_bandstop", "height_estimator.HeightEstimator", "scenario.Path",
         "corner_table.main", "corner_validation.read_measured", "os.system", "builtins.eval",
         "registry.factory", "fopdt.PI.__init__", "fopdt.__class__", "fopdt:PI",
         "plants.fopdt:PI", "os:system", "gymnasium", "gymnasium:CartPole-v1",
         "CartPole-v1", "__main__.x", "fopdt", "edm_sink", "milling", "wedm_gap", "fopdt.",
         ".PI", "fopdt..PI", "../fopdt", "/dev/zero", "/dev/stdin", "/proc/self/mem", "-",
         "fopdt_pi.fz", "../rulebases/fopdt_pi.fz", "/etc/passwd", "nonexistent.fz")
YAML_WORDS = (".nan", ".NaN", ".inf", "-.inf", "+.inf", "~", "null", "Null", "true", "false",
              "yes", "no", "on", "off", "y", "n", "1:30", "190:20:30", "2001-12-14",
              "2001-12-14t21:59:43.10-05:00", "0o17", "017", "0x1F", "0b101", "1_000", "+1",
              "!!binary aGVsbG8=", "!!float 1", "!!int 1.5", "!!str 1", "!!bool maybe",
              "!!null x", "!!set {a}", "!!omap [a: 1]", "!!pairs [a: 1]", "!!timestamp 2001",
              "!!python/name:os.system", "!!python/object/apply:os.system [id]", "!local 1",
              "!!map [1]", "!!seq {a: 1}", "<<", "=", "? a", "''", '""', "'a''b'", "|", ">",
              "- a", "&a", "*a", "*undefined", "&a &b 1", "!", "%", "@", "`")
DEEP = (31, 32, 33, 100, 1000)


def _bomb(rnd: random.Random) -> str:
    """Nested aliases that stand for width**levels values in a few hundred bytes (refused
    while composing), or an alias inside its own anchor, or to no anchor."""
    kind = rnd.randint(0, 3)
    if kind == 0:
        width, levels = rnd.choice(((9, 9), (10, 6), (4, 20), (2, 40))), None
        width, levels = width
        parts = ["&b0 [" + ", ".join(["lol"] * width) + "]"]
        parts += [f"&b{i} [" + ", ".join([f"*b{i - 1}"] * width) + "]" for i in range(1, levels)]
        return "[" + ", ".join(parts) + "]"
    if kind == 1:
        return "&s [*s]" if rnd.random() < 0.5 else "&m {a: *m}"
    if kind == 2:
        return "[&k {a: 1}, {<<: *k, b: 2}, {<<: [*k, *k]}]"
    return rnd.choice(("*nope", "[&a 1, *a, *b]", "{&a a: 1, *a : 2}"))


def yaml_value(rnd: random.Random, depth: int = 0) -> str:
    """One YAML value in flow style, of any YAML type."""
    kind = rnd.randint(0, 13 if depth < 3 else 5)
    if kind == 0:
        return number(rnd, -1e3, 1e3)
    if kind == 1:
        return rnd.choice(HOSTILE_NUMBERS) or "''"
    if kind == 2:
        return rnd.choice(YAML_WORDS)
    if kind == 3:
        return json.dumps(name(rnd))          # a JSON string is a YAML double-quoted string
    if kind == 4:
        return json.dumps(rnd.choice(MAKES)) if rnd.random() < 0.5 else rnd.choice(MAKES)
    if kind == 5:
        return str(rnd.choice((0, 1, -1, 10 ** 12, 2 ** 63, 10 ** 400, int("9" * 999))))
    if kind in (6, 7):
        return "[" + ", ".join(yaml_value(rnd, depth + 1) for _ in range(rnd.randint(0, 4))) + "]"
    if kind in (8, 9):
        return "{" + ", ".join(f"{yaml_key(rnd)}: {yaml_value(rnd, depth + 1)}"
                               for _ in range(rnd.randint(0, 3))) + "}"
    if kind == 10:
        n = rnd.choice(DEEP)
        return rnd.choice(("[" * n + "]" * n, "{a: " * n + "1" + "}" * n,
                           "[{a: " * (n // 2) + "1" + "}]" * (n // 2)))
    if kind == 11:
        return _bomb(rnd)
    if kind == 12:      # a pair list as the schedules take, with hostile points
        return "[" + ", ".join(f"[{number(rnd, 0, 1)}, {number(rnd, -5, 5)}]"
                               for _ in range(rnd.randint(0, 4))) + "]"
    if rnd.random() < 0.8:      # the values past a limit take PyYAML a second to scan: rarer
        return rnd.choice(("[" * 40 + "]" * 40, "&big [" + "1, " * 1000 + "1]"))
    return rnd.choice(("[" + "1, " * 250_000 + "1]",        # past the node limit
                       '"' + "x" * 1_100_000 + '"',         # past the size limit
                       "&big [" + "1, " * 1000 + "1]"))


def yaml_key(rnd: random.Random) -> str:
    from fuzzyc.plants.scenario_schema import METRIC_KEYS, OBSERVER_KEYS, TOP_KEYS
    kind = rnd.random()
    if kind < 0.6:
        return rnd.choice(sorted(TOP_KEYS | METRIC_KEYS | OBSERVER_KEYS))
    if kind < 0.8:
        return json.dumps(name(rnd))
    return rnd.choice(("1", "1.5", "null", "~", "true", "[1]", "{a: 1}", ".nan", "<<", "? x",
                       "*a", '""', "''"))


def schema_paths(data) -> list[tuple]:
    """Every key path of a scenario (and of every list item) plus every key the schema knows,
    so each gets a hostile value in turn."""
    from fuzzyc.plants.scenario_schema import (METRIC_KEYS, OBSERVER_KEYS, SECTION_KEYS,
                                        TOP_KEYS)
    paths = set()

    def walk(node, prefix):
        items = node.items() if isinstance(node, dict) else \
            enumerate(node) if isinstance(node, list) else ()
        for key, value in items:
            paths.add(prefix + (key,))
            walk(value, prefix + (key,))
    walk(data, ())
    paths |= {(k,) for k in TOP_KEYS}
    paths |= {(s, k) for s, keys in SECTION_KEYS.items() for k in keys}
    paths |= {("observers", 0, k) for k in OBSERVER_KEYS} | {("metrics", 0, k) for k in METRIC_KEYS}
    paths |= {("plant", "params", "x"), ("controller", "params", "GU"), ("schedules", "r"),
              ("schedules", "r", 0), ("schedules", "r", 0, 0), ("initial", "y")}
    return sorted(paths, key=str)


def _number_at(data, path: tuple):
    for key in path:
        try:
            data = data[key]
        except (KeyError, IndexError, TypeError):
            return None
    return data if isinstance(data, (int, float)) and not isinstance(data, bool) else None


class Raw(str):
    """Already YAML text: emitted as it is."""


def emit(value) -> str:
    """Flow-style YAML of a loaded scenario in which some values are Raw text."""
    if isinstance(value, Raw):
        return value
    if isinstance(value, dict):
        return "{" + ", ".join(f"{k if isinstance(k, Raw) else json.dumps(k)}: {emit(v)}"
                               for k, v in value.items()) + "}"
    if isinstance(value, list):
        return "[" + ", ".join(emit(v) for v in value) + "]"
    return json.dumps(value, default=str)


def _put(data, path: tuple, value) -> None:
    node = data
    for key in path[:-1]:
        if isinstance(node, list):
            if not node:
                node.append({})
            key = min(key, len(node) - 1) if isinstance(key, int) else 0
        elif not isinstance(node, dict):
            return
        elif not isinstance(node.get(key), (dict, list)):
            node[key] = {}
        node = node[key]
    last = path[-1]
    if isinstance(node, dict):
        if value is None:
            node.pop(last, None)
        else:
            node[last] = value
    elif isinstance(node, list) and node and isinstance(last, int):
        node[min(last, len(node) - 1)] = Raw("~") if value is None else value


def scenario_text(rnd: random.Random, base: dict) -> str:
    """A shipped scenario (short) with one to three keys of the schema given hostile values
    (or removed, or an unknown key added), written as YAML."""
    import copy
    data = copy.deepcopy(base)
    if rnd.random() < 0.03:                     # a document that is no mapping at all
        return yaml_value(rnd) + "\n"
    paths = schema_paths(data)
    for _ in range(rnd.randint(1, 3)):
        path = rnd.choice(paths)
        kind = rnd.random()
        if kind < 0.1:
            _put(data, path, None)
        elif kind < 0.2:
            _put(data, path[:-1] + (Raw(yaml_key(rnd)),), Raw(yaml_value(rnd)))
        elif kind < 0.5 and _number_at(base, path) is not None:
            # a plausible number where one is, so that some scenarios run with odd values
            value = _number_at(base, path) * rnd.choice((0, -1, 0.5, 2, 1e-3, 1e-9))
            _put(data, path, Raw(repr(value)))
        else:
            _put(data, path, Raw(yaml_value(rnd)))
    lines = [f"{k if isinstance(k, Raw) else json.dumps(k)}: {emit(v)}" for k, v in data.items()]
    rnd.shuffle(lines)        # an anchor may come after its alias
    head = rnd.choice(("", "", "", "%YAML 1.1\n---\n", "--- !!map\n", "\ufeff"))
    tail = rnd.choice(("", "", "", "...\n", "---\nplant: {model: fopdt}\n", "\t\n"))
    return head + "\n".join(lines) + "\n" + tail


# -- rule bases --------------------------------------------------------------------------------

HEDGES = ("very", "somewhat", "extremely", "seldom", "any", "not")
FLL_SHAPES = {"Triangle": 3, "Trapezoid": 4, "Rectangle": 2, "Ramp": 2, "Sigmoid": 2,
              "Gaussian": 2, "Bell": 3, "SShape": 2, "ZShape": 2, "PiShape": 4, "Spike": 2,
              "Cosine": 2, "Concave": 2, "GaussianProduct": 4, "SigmoidDifference": 3,
              "SigmoidProduct": 4, "Discrete": 4, "Binary": 2, "Constant": 1, "Linear": 3,
              "Function": 1, "Nope": 2}
FCL_SHAPES = {"TRIAN": 3, "TRAPE": 4, "GAUSS": 2, "GBELL": 3, "SIGM": 2, "POINTS": 0,
              "SINGLETON": 1, "COSINE": 2}
FIS_SHAPES = {"trimf": 3, "trapmf": 4, "gaussmf": 2, "gauss2mf": 4, "gbellmf": 3, "sigmf": 2,
              "dsigmf": 4, "psigmf": 4, "pimf": 4, "smf": 2, "zmf": 2, "constant": 1,
              "linear": 3, "foomf": 2}


def _count(rnd: random.Random, usual: int, far: tuple[int, ...]) -> int:
    """Mostly 1..usual, now and then one of the `far` sizes (limits and past them)."""
    return rnd.choice(far) if rnd.random() < 0.08 else rnd.randint(1, usual)


def _variable(rnd: random.Random, names: bool, clean: bool, i: int) -> dict:
    lo = rnd.uniform(-100, 100)
    hi = lo + rnd.uniform(0.1, 200)
    hostile = 0.0 if clean else 0.08
    terms = [{"name": name(rnd) if names else f"t{i}",
              "params": [number(rnd, lo, hi, hostile) for _ in range(4)]}
             for i in range(rnd.randint(1, 4) if clean else _count(rnd, 4, (0, 50, 253, 254, 300)))]
    return {"name": name(rnd) if names else f"v{i}",
            "lo": number(rnd, lo, lo, hostile), "hi": number(rnd, hi, hi, hostile), "terms": terms}


def rulebase(rnd: random.Random, names: bool = False) -> dict:
    """A random rule base: 1-3 inputs, 1-2 outputs, rules of random depth and hedges;
    with `names`, hostile names everywhere a name stands. Half are `clean`: shapes whose
    parameters are in order, no hostile number, hedges and depths within the limits, so that
    they pass `check` and reach eval, convert and compile."""
    clean = rnd.random() < 0.5
    n_in = rnd.randint(1, 3) if clean else _count(rnd, 3, (0, 32, 33))
    n_out = rnd.randint(1, 2) if clean else _count(rnd, 2, (0, 33))
    inputs = [_variable(rnd, names, clean, i) for i in range(n_in)]
    outputs = [_variable(rnd, names, clean, n_in + i) for i in range(n_out)]
    rules = []
    for _ in range(rnd.randint(1, 6) if clean else _count(rnd, 6, (0, 200, 2000))):
        depth = rnd.choice((0, 1, 2, 3, 5, rnd.choice((20, 50) if clean else
                                                       (50, 199, 200, 201, 1000))))
        rules.append({"if": _condition(rnd, inputs, depth, clean),
                      "then": [_clause(rnd, outputs, conclusion=True, clean=clean)
                               for _ in range(rnd.randint(1, 2))],
                      "weight": rnd.choice((None, None, None, number(rnd, 0, 1, 0 if clean else 0.08)))})
    return {"name": name(rnd) if names else "gen", "inputs": inputs, "outputs": outputs,
            "rules": rules, "kind": rnd.choice(("mamdani", "mamdani", "sugeno")), "clean": clean}


def _clause(rnd, variables, conclusion=False, clean=False) -> tuple:
    var = rnd.choice(variables) if variables else {"name": "nothing", "terms": []}
    term = rnd.choice(var["terms"])["name"] if var["terms"] and (clean or rnd.random() < 0.95) \
        else name(rnd)
    far = (16, 17, 300) if not conclusion else (16, 17)
    count = 0 if clean and conclusion else rnd.choice((0, 0, 0, 1, 2, 16)) if clean else \
        rnd.choice(far) if rnd.random() < 0.05 else rnd.choice((0, 0, 0, 1, 2))
    hedges = [rnd.choice(HEDGES[:4] if clean else HEDGES) for _ in range(count)]
    return ("is", var["name"], term, hedges)


def _condition(rnd, inputs, depth: int, clean: bool = False) -> tuple:
    """A clause and `depth` steps (op, clause, whether the clause goes left), each step
    nesting what came before one level deeper."""
    steps = [(rnd.choice(("and", "or", "and", "or", "not")), _clause(rnd, inputs, clean=clean),
              rnd.random() < 0.5) for _ in range(depth)]
    return _clause(rnd, inputs, clean=clean), steps


def _sentence(condition, words: dict, rnd: random.Random) -> str:
    """A condition as FLL (lower-case words) or FCL (upper-case) text, brackets around every
    compound part (and around a few clauses, which must be allowed too); built in a loop, not
    recursively, so that 1,000 levels are no problem of the harness's."""
    def clause(node):
        _, var, term, hedges = node
        text = f"{var} {words['is']} {' '.join([*hedges, term])}"
        return f"({text})" if rnd.random() < 0.05 else text
    first, steps = condition
    text = clause(first)
    for i, (op, other, left) in enumerate(steps):
        inner = f"({text})" if i else text
        text = f"{words['not']} {inner if i else f'({inner})'}" if op == "not" else \
            f"{clause(other)} {words[op]} {inner}" if left else \
            f"{inner} {words[op]} {clause(other)}"
    return text


def fll_text(rb: dict, rnd: random.Random) -> str:
    lines = [f"Engine: {rb['name']}"]
    for kind, variables in (("Input", rb["inputs"]), ("Output", rb["outputs"])):
        for v in variables:
            lines += [f"{kind}Variable: {v['name']}", f"  range: {v['lo']} {v['hi']}"]
            if kind == "Output":
                sugeno = rb["kind"] == "sugeno"
                lines += [f"  aggregation: {'none' if sugeno else 'Maximum'}",
                          f"  defuzzifier: {'WeightedAverage' if sugeno else 'Centroid 100'}",
                          f"  default: {rnd.choice(('0', '5') if rb['clean'] else ('0', 'nan', '1e400', '5'))}"]
            for t in v["terms"]:
                shape = rnd.choice(("Constant", "Linear")) if kind == "Output" and \
                    rb["kind"] == "sugeno" else rnd.choice(CLEAN_FLL if rb["clean"] else list(FLL_SHAPES))
                count = len(rb["inputs"]) + 1 if shape == "Linear" else FLL_SHAPES[shape]
                params = sorted((t["params"] * 9)[:count], key=_as_float)
                lines.append(f"  term: {t['name']} {shape} {' '.join(params)}")
    lines += ["RuleBlock: rules", "  conjunction: Minimum", "  disjunction: Maximum",
              "  implication: Minimum", "  activation: General"]
    words = {"is": "is", "and": "and", "or": "or", "not": "not"}
    for r in rb["rules"]:
        then = " and ".join(f"{var} is {' '.join([*h, term])}" for _, var, term, h in r["then"])
        weight = f" with {r['weight']}" if r["weight"] else ""
        lines.append(f"  rule: if {_sentence(r['if'], words, rnd)} then {then}{weight}")
    return "\n".join(lines) + "\n"


def fcl_text(rb: dict, rnd: random.Random) -> str:
    lines = [f"FUNCTION_BLOCK {rb['name']}", "VAR_INPUT"]
    lines += [f"  {v['name']} : REAL;" for v in rb["inputs"]] + ["END_VAR", "VAR_OUTPUT"]
    lines += [f"  {v['name']} : REAL;" for v in rb["outputs"]] + ["END_VAR"]
    for kind, variables in (("FUZZIFY", rb["inputs"]), ("DEFUZZIFY", rb["outputs"])):
        for v in variables:
            lines.append(f"{kind} {v['name']}")
            for t in v["terms"]:
                shape = rnd.choice(CLEAN_FCL if rb["clean"] else list(FCL_SHAPES))
                params = sorted(t["params"], key=_as_float)
                if shape == "POINTS":
                    body = " ".join(f"({x}, {rnd.choice(('0', '1', '0.5') if rb['clean'] else ('0', '1', '0.5', '2', 'nan'))})"
                                    for x in params[:rnd.randint(1, 4)])
                elif shape == "SINGLETON":
                    body = params[0]
                else:
                    body = f"{shape} {' '.join(params[:FCL_SHAPES[shape]])}"
                lines.append(f"  TERM {t['name']} := {body};")
            lines.append(f"  RANGE := ({v['lo']} .. {v['hi']});")
            if kind == "DEFUZZIFY":
                lines += [f"  METHOD : {'COG' if rb['clean'] else rnd.choice(('COG', 'COA', 'LM', 'RM', 'MM', 'COGS'))};",
                          f"  DEFAULT := {'0' if rb['clean'] else rnd.choice(('0', 'NC', 'nan', '1e400'))};"]
            lines.append(f"END_{kind}")
    lines += ["RULEBLOCK rules", "  AND : MIN;", "  OR : MAX;", "  ACT : MIN;", "  ACCU : MAX;"]
    words = {"is": "IS", "and": "AND", "or": "OR", "not": "NOT"}
    for i, r in enumerate(rb["rules"], 1):
        then = ", ".join(f"{var} IS {' '.join([*h, term])}" for _, var, term, h in r["then"])
        weight = f" WITH {r['weight']}" if r["weight"] else ""
        lines.append(f"  RULE {i} : IF {_sentence(r['if'], words, rnd)} THEN {then}{weight};")
    return "\n".join(lines + ["END_RULEBLOCK", "END_FUNCTION_BLOCK"]) + "\n"


def fis_text(rb: dict, rnd: random.Random) -> str:
    """FIS has no nesting: each rule an index row (negative: NOT, .2 .05 .3: hedges)."""
    sugeno = rb["kind"] == "sugeno"
    lines = ["[System]", f"Name='{rb['name']}'", f"Type='{rb['kind']}'", "Version=2.0",
             f"NumInputs={len(rb['inputs'])}", f"NumOutputs={len(rb['outputs'])}",
             f"NumRules={len(rb['rules'])}", "AndMethod='min'", "OrMethod='max'",
             "ImpMethod='min'", "AggMethod='max'",
             f"DefuzzMethod='{'wtaver' if sugeno else 'centroid'}'"]
    for kind, variables in (("Input", rb["inputs"]), ("Output", rb["outputs"])):
        for i, v in enumerate(variables, 1):
            lines += ["", f"[{kind}{i}]", f"Name='{v['name']}'", f"Range=[{v['lo']} {v['hi']}]",
                      f"NumMFs={len(v['terms'])}"]
            for j, t in enumerate(v["terms"], 1):
                shape = rnd.choice(("constant", "linear")) if kind == "Output" and sugeno \
                    else rnd.choice(CLEAN_FIS if rb["clean"] else list(FIS_SHAPES))
                count = len(rb["inputs"]) + 1 if shape == "linear" else FIS_SHAPES[shape]
                params = sorted((t["params"] * 3)[:count], key=_as_float)
                lines.append(f"MF{j}='{t['name']}':'{shape}',[{' '.join(params)}]")
    lines += ["", "[Rules]"]
    for r in rb["rules"]:
        def index(variables):
            v = rnd.choice(variables) if variables else {"terms": []}
            if rb["clean"]:
                return f"{rnd.choice(('', '', '-'))}{rnd.randint(1, len(v['terms']))}" \
                    f"{rnd.choice(('', '', '.2', '.05'))}"
            k = rnd.randint(0, len(v["terms"]) + (1 if rnd.random() < 0.05 else 0))
            return f"{rnd.choice(('', '', '-'))}{k}{rnd.choice(('', '', '.2', '.05', '.3', '.7'))}"
        ins = " ".join(index(rb["inputs"]) for _ in rb["inputs"])
        outs = " ".join(index(rb["outputs"]) for _ in rb["outputs"])
        lines.append(f"{ins}, {outs} ({r['weight'] or 1}) : "
                     f"{rnd.choice((1, 2) if rb['clean'] else (1, 2, 1, 2, 3))}")
    return "\n".join(lines) + "\n"


def _as_float(text: str) -> float:
    try:
        value = float(text)
    except ValueError:
        return 0.0
    return value if value == value else 0.0


# shapes whose sorted parameters are valid, for the clean half
CLEAN_FLL = ("Triangle", "Trapezoid", "Ramp", "Rectangle")
CLEAN_FCL = ("TRIAN", "TRAPE", "POINTS")
CLEAN_FIS = ("trimf", "trapmf")
RULE_WRITERS = {".fll": fll_text, ".fcl": fcl_text, ".fis": fis_text}


# -- API values --------------------------------------------------------------------------------

DTYPES = ("int8", "int16", "int32", "int64", "uint8", "uint16", "uint32", "uint64", "float16",
          "float32", "float64", "longdouble", "complex64", "complex128", "bool", "object",
          "U3", "S3", "datetime64[s]", "timedelta64[ms]", "V4", "f4,i4")
SHAPES = ((), (0,), (1,), (3,), (4,), (2, 3), (0, 3), (3, 1), (1, 1, 1), (2, 0, 2), (100_000,))


def api_value(rnd: random.Random):
    """A value for one input of `fuzzyc.evaluate`: Python objects, numpy scalars and arrays of
    every dtype and shape."""
    import numpy as np
    if rnd.random() < 0.5:
        return rnd.choice((rnd.uniform(-1e3, 1e3), np.linspace(0, 10, 3), [1.0, 2.0, 3.0],
                           np.float32(2.5), 7, np.arange(6).reshape(2, 3), np.nan))
    kind = rnd.randint(0, 5)
    if kind == 0:
        return rnd.choice((None, True, False, 0, 1, -1, 2.5, float("nan"), float("inf"),
                           10 ** 400, -10 ** 400, 2 ** 64, "1.5", "abc", "", b"1", [], [[]],
                           [1, [2]], [[1, 2], [3]], (1, 2), [1, None], [1, "2"], {1: 2}, {1},
                           1 + 2j, Decimal("1.5"), Decimal("NaN"), Fraction(1, 3), object(),
                           len, range(3), iter([1]), [10 ** 400], [True, 1]))
    if kind == 1:
        return rnd.choice((np.float64("nan"), np.float32(1e38), np.int64(2 ** 63 - 1),
                           np.uint64(2 ** 64 - 1), np.float16(65504), np.longdouble("1e4000"),
                           np.complex128(1 + 1j), np.bool_(True), np.str_("1"), np.bytes_(b"1"),
                           np.datetime64("2020-01-01"), np.timedelta64(5, "s"), np.void(b"ab")))
    dtype, shape = rnd.choice(DTYPES), rnd.choice(SHAPES)
    try:
        array = np.zeros(shape, dtype=dtype)
    except (TypeError, ValueError):
        array = np.zeros(shape)
    if array.dtype.kind in "fc" and array.size:
        with np.errstate(over="ignore"):           # 1e300 in a float16 is inf: meant
            array.flat[rnd.randrange(array.size)] = rnd.choice((np.nan, np.inf, -np.inf, 1e300, 5))
    elif array.dtype.kind in "iu" and array.size:
        array.flat[rnd.randrange(array.size)] = np.iinfo(array.dtype).max
    elif array.dtype.kind == "O" and array.size:
        array.flat[rnd.randrange(array.size)] = rnd.choice((None, "x", 10 ** 400, [1], 1.5))
    if kind == 3:
        return np.ma.masked_array(array, mask=rnd.random() < 0.5)
    if kind == 4 and array.ndim >= 2:
        return np.asfortranarray(array)[::-1]
    if kind == 5 and array.ndim >= 1 and array.dtype.kind in "fiu":
        return np.lib.stride_tricks.as_strided(array, shape=(rnd.choice((2, 1000)),),
                                               strides=(0,))
    return array


# -- hypothesis entry ---------------------------------------------------------------------------

def rng() -> st.SearchStrategy[random.Random]:
    """A random.Random seeded by hypothesis: the input is reproducible from --seed."""
    return st.integers(0, 2 ** 63 - 1).map(random.Random)
