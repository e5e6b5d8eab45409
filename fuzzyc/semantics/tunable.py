"""What `fuzzyc tune` may move: one record per tuned number, and the table of term-parameter
names the `tune { ... }` section uses.

A tuned number is a number written in the file (a term's parameter as written, a rule weight,
a param's value) with the bounds it may move in; every other number is frozen.  The builder
(fuzzyc.language.builder.tunables) makes the records, the tuner (fuzzyc.tune) moves them, the
.fz writer writes them back as `tune` lines.
"""
from __future__ import annotations

from dataclasses import dataclass

from .model import SourceLoc, TermKind

# A shape's written numbers by name, in the order they are written (`bell(center, width,
# slope)`).  A name may be given in several spellings: the first is the one the writer uses.
PARAMETER_NAMES: dict[str, tuple[tuple[str, ...], ...]] = {
    "tri": (("a", "left"), ("b", "center", "peak"), ("c", "right")),
    "trap": (("a",), ("b",), ("c",), ("d",)),
    "lshoulder": (("c",), ("d",)),
    "rshoulder": (("a",), ("b",)),
    "gauss": (("mean", "center"), ("sigma", "width")),
    "bell": (("center",), ("width",), ("slope",)),
    "sigmoid": (("center",), ("slope",)),
    "singleton": (("value",),),
    "sshape": (("start",), ("end",)),
    "zshape": (("start",), ("end",)),
    "pishape": (("a",), ("b",), ("c",), ("d",)),
    "spike": (("center",), ("width",)),
    "cosine": (("center",), ("width",)),
    "concave": (("inflection",), ("end",)),
    "sigmoid_difference": (("left",), ("rising",), ("falling",), ("right",)),
    "sigmoid_product": (("left",), ("rising",), ("falling",), ("right",)),
    "gaussian_product": (("mean_a",), ("sigma_a",), ("mean_b",), ("sigma_b",)),
    "binary": (("start",), ("direction",)),
    "semi_ellipse": (("start",), ("end",)),
    "arc": (("start",), ("end",)),
}

# Written numbers that must stay above 0 (widths, slopes), by shape and written index
POSITIVE = {"gauss": (1,), "bell": (1, 2), "spike": (1,), "cosine": (1,),
            "gaussian_product": (1, 3)}
# Written numbers that stay in order, as pairs (i, j, strict): number i <= (<) number j
ORDERED = {"tri": ((0, 1, False), (1, 2, False), (0, 2, True)),
           "trap": ((0, 1, False), (1, 2, False), (2, 3, False), (0, 3, True)),
           "lshoulder": ((0, 1, True),), "rshoulder": ((0, 1, True),),
           "sshape": ((0, 1, True),), "zshape": ((0, 1, True),),
           "pishape": ((0, 1, True), (2, 3, True))}
# Where a written number goes among the model's 4 params (tri b is both b and c)
SLOTS = {"tri": ((0,), (1, 2), (3,)), "lshoulder": ((2,), (3,)), "rshoulder": ((0,), (1,))}


def parameter_names(shape: str, count: int) -> list[tuple[str, ...]]:
    """The names of a term's `count` written numbers: linear c0..cn, discrete x1 y1 x2 y2..."""
    if shape == "linear":
        return [(f"c{i}",) for i in range(count)]
    if shape == "discrete":
        return [(f"{'xy'[i % 2]}{i // 2 + 1}",) for i in range(count)]
    return list(PARAMETER_NAMES.get(shape, ()))[:count]


def slots(shape: str, index: int) -> tuple[int, ...]:
    """The model params (Variable.params columns) written number `index` of a shape sets."""
    return SLOTS.get(shape, ())[index] if shape in SLOTS else (index,)


def shape_word(kind: TermKind, params) -> str:
    """The shape word the .fz writer uses for a term of the model (as fuzzyc.formats.fz)."""
    from ..language.builder.terms import PLAIN_SHAPES
    if kind == TermKind.TRAPEZOID:
        a, b, c, d = (float(x) for x in params)
        if a == b == -float("inf"):
            return "lshoulder"
        if c == d == float("inf"):
            return "rshoulder"
        return "tri" if b == c else "trap"
    words = {TermKind.GAUSSIAN: "gauss", TermKind.BELL: "bell", TermKind.SIGMOID: "sigmoid",
             TermKind.SINGLETON: "singleton", TermKind.LINEAR: "linear",
             TermKind.DISCRETE: "discrete",
             **{k: w for w, (k, *_) in PLAIN_SHAPES.items()}}
    return words[TermKind(int(kind))]


@dataclass(frozen=True)
class TunedNumber:
    """One number `fuzzyc tune` may move within [lo, hi].

    kind "term": number `index` of term `term` of variable `var` as written (`shape`), which
    sets the model params `slots` of that term in every block that has the variable (a LINEAR
    term with more than 4 numbers: Variable.coefficients, a DISCRETE one: Variable.points).
    kind "weight": the weight of the rule named `rule` (rule `rule_index` of block `block`).
    kind "param": the value of param `param`.
    `token`: where the number is written (None: a rule without `with w`, whose weight is then
    written at `insert_at`, the end of the rule); `loc`: the `tune` line that frees it, in the
    statement spanning `section`; `spread`: its bound was said relative to the written value
    (a tuned file says it absolute: the value it was relative to has moved)."""
    kind: str
    target: str               # e.g. "e.NB.b", "r1.weight", "GE"
    value: float              # as written
    lo: float
    hi: float
    loc: SourceLoc | None = None
    token: SourceLoc | None = None
    insert_at: SourceLoc | None = None
    var: str = ""
    term: str = ""
    shape: str = ""
    index: int = 0
    slots: tuple[int, ...] = ()
    rule: str = ""
    block: int = 0
    rule_index: int = 0
    param: str = ""
    spread: bool = False      # bounded as `+/- d` around the written value
    section: tuple[SourceLoc, SourceLoc] | None = None   # its `tune { ... }`, start and end
