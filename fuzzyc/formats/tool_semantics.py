"""Other tools' arithmetic, for users checking a migration: `evaluate_as(rb, x, semantics)`.

fuzzyc's own semantics ("exact") integrate the integral defuzzifiers exactly.  The tools sample:
- "fuzzylite" (the fuzzylite 6 C++ library and CLI) and "pyfuzzylite" (pyfuzzylite 8): the
  midpoint rule at the output's resolution (fuzzylite_compat; default 100 in fuzzylite 6, 1000
  in pyfuzzylite 8), and NaN where no rule concluding an output fired (fuzzylite's
  `default: nan`, which its examples use).  fuzzylite 6's WeightedAverage sums over the rules
  whatever the aggregation (measured: the shipped WEDM rule bases exported as FLL, 0.28 apart
  from the grouped value), pyfuzzylite 8 groups the rules of a term with it (CENTER_OF_AREA);
- "matlab": MATLAB's evalfis as documented: Mamdani outputs sampled as "octave" below (but
  the output's default, the middle of the range, where nothing fired, the exact bisector and
  the pairwise folds of the norms), Sugeno outputs summed over the rules (WEIGHTED_AVERAGE,
  exact); not checked against MATLAB (none here);
- "octave" (the Octave fuzzy-logic-toolkit 0.4.6 evalfis, also MATLAB's num_points = 101):
  the aggregated set sampled at linspace(lo, hi, 101) and integrated with trapz, so
  Centroid = trapz(u, u M) / trapz(u, M); MeanOfMaximum = the mean of the samples where M equals
  its maximum; its bisector returns the index (1..101) of the sample it stops at, not the
  sample (defuzz.m), and that is what "octave" gives ("matlab": exact); where nothing fired
  defuzz.m's own values on a set that is 0 throughout (centroid NaN, mom the middle, som/lom
  the ends, bisector 101).  Its aggregation drastic_sum takes the column of every rule at once
  (drastic_sum.m: the max where some rule's value is 0, else 1; a rule not concluding the
  output counts as 0), not the pairwise fold (fuzzylite_compat.octave_drastic_sum).
  Sugeno outputs: the rules' values that are equal are merged with the AggMethod before the
  weighted average (so `max` takes the strongest rule per term: CENTER_OF_AREA with that
  aggregation), where MATLAB sums over every rule (fuzzyc's WEIGHTED_AVERAGE).
Peak-based defuzzifiers (weighted average/sum, center of area) are exact in every tool.
Hedges: fuzzylite's `extremely` is its S-curve, and a FIS hedge on a consequent (CondOp.CONCLUDED,
the Octave toolkit's strength^(1/p) in the exact semantics) acts on the activation and carries
on to the row's later conclusions (`fuzzylite_hedges`).
Tsukamoto (fuzzylite only): pyfuzzylite 8 inverts the terms exactly without clipping (a sigmoid
at activation 1 gives an infinite output); fuzzylite 6 (measured against its CLI on
tsukamoto.fll, and read off as these rules) takes a Sigmoid's range end within 1e-6 of
activation 0 or 1, picks for S/Z shapes the closer of two candidates of which one lies beyond
the term's end, and inverts a Concave at its own membership of the activation.

A semantics is written NAME or NAME:RESOLUTION (`fuzzylite:200`, the file's `Centroid 200`).
`ToolEngine` evaluates so inside the controller (eval, simulate); the C back end and the
verifier compute exactly, so `exact_equivalent` gives them the rule base whose exact numbers are
the tool's (fuzzylite 6's weighted average over the rules) or says why there is none (a sampled
integral, Octave's merging of equal Sugeno values).
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field, replace
from typing import Sequence

import numpy as np

from ..engine.inference import activations, evaluate, flat_activations, run_condition
from ..errors import Diagnostic, FuzzycError
from ..engine.membership import (HEDGE_EXPONENT, apply_hedges, linear_coefficients, memberships,
                                 pointwise, term_inverse)
from ..semantics.model import (Aggregation, CondOp, Connective, Defuzzifier, Hedge, Model,
                               RuleBase, SNorm, TermKind, TNorm, Variable, aggregation_snorm,
                               weight_of)
from ..engine.norms import S_NORMS, T_NORMS, combine, firing
from ..engine.formula import Formula, parse_formula
from ..engine.held_outputs import POLICIES, Held, reads_values
from .fuzzylite_compat import FL6_S, FL6_T, FL_EPSILON, SAMPLED, Sampling, evaluate_sampled

SEMANTICS = ("exact", "fuzzylite", "pyfuzzylite", "matlab", "octave")
RESOLUTION = {"fuzzylite": 100, "pyfuzzylite": 1000}
OCTAVE_POINTS = 101
# the Octave toolkit samples these ("octave" adds its bisector, which returns an index)
OCTAVE_SAMPLED = (Defuzzifier.CENTROID, Defuzzifier.MEAN_OF_MAXIMUM,
                  Defuzzifier.SMALLEST_OF_MAXIMUM, Defuzzifier.LARGEST_OF_MAXIMUM)


def parse_semantics(text: str) -> tuple[str, int | None]:
    """`NAME` or `NAME:RESOLUTION` -> (name, resolution or None); FuzzycError when unknown."""
    name, _, points = text.partition(":")
    if name not in SEMANTICS or (points and not (points.isdigit() and int(points) > 1)):
        raise FuzzycError([Diagnostic(None, f"--semantics `{text}`: one of "
                                            f"{', '.join(SEMANTICS)}, optionally :RESOLUTION "
                                            "(an integer > 1, e.g. fuzzylite:200)")])
    return name, int(points) if points else None


# fuzzylite 6's WeightedAverage and WeightedSum weigh every rule's value, whatever the
# aggregation (Defuzzifier.cpp of fuzzylite 6: no grouping, which pyfuzzylite 8 added)
OVER_RULES = {Defuzzifier.CENTER_OF_AREA: Defuzzifier.WEIGHTED_AVERAGE,
              Defuzzifier.GROUPED_SUM: Defuzzifier.WEIGHTED_SUM}


def _over_rules(rb: RuleBase) -> RuleBase:
    """fuzzylite 6's WeightedAverage and WeightedSum: every rule's value weighted, whatever
    the aggregation (the block's and each output's own center of area or grouped sum)."""
    inference = replace(rb.inference, defuzzifier=OVER_RULES.get(rb.inference.defuzzifier,
                                                                  rb.inference.defuzzifier))
    choices = {name: (agg, OVER_RULES.get(d, d)) for name, (agg, d) in rb.output_choices.items()}
    return replace(rb, inference=inference, output_choices=choices)


def _any_center_of_area(rb: RuleBase) -> bool:
    """Whether some output groups its rules per term (fuzzylite 6 does not)."""
    return any(rb.inference_of(o).defuzzifier in OVER_RULES for o in range(len(rb.outputs)))


def exact_equivalent(rb: RuleBase, semantics: str) -> tuple[RuleBase, str | None]:
    """(a rule base whose exact numbers are the tool's, None), or (rb, why there is none)."""
    name, _ = parse_semantics(semantics)
    if name == "exact":
        return rb, None
    if name in ("fuzzylite", "pyfuzzylite"):
        rb = fuzzylite_hedges(rb)
    for inf in [rb.inference_of(o) for o in range(len(rb.outputs))] or [rb.inference]:
        if inf.defuzzifier in SAMPLED:
            return rb, (f"{name} samples the {inf.defuzzifier.name.lower()} "
                        f"({RESOLUTION.get(name, OCTAVE_POINTS)} points by default) where "
                        "fuzzyc integrates exactly")
        if name == "octave" and inf.defuzzifier == Defuzzifier.WEIGHTED_AVERAGE \
                and inf.aggregation != Aggregation.SUM:
            return rb, ("the Octave toolkit merges the Sugeno rules of equal value with "
                        f"AggMethod {inf.aggregation.name.lower()} where fuzzyc sums over the "
                        "rules")
    if name == "fuzzylite" and _any_center_of_area(rb):
        return _over_rules(rb), None
    return rb, None


def with_tool_semantics(model: Model, semantics: str, command: str) -> Model:
    """The model whose exact numbers are the tool's, for what computes exactly (compile,
    verify, the C controller), or FuzzycError saying why the tool's numbers cannot be had so."""
    flat = file_settings(model).flat if parse_semantics(semantics)[0] in (
        "fuzzylite", "pyfuzzylite") else set()
    done = [exact_equivalent(fuzzylite_flat(rb, flat), semantics) for rb in model.blocks]
    for _, reason in done:
        if reason:
            raise FuzzycError([Diagnostic(None, f"{command} --semantics {semantics}: {reason}; "
                                                f"{command} computes exactly (eval and simulate "
                                                "follow the tool)")])
    model.blocks = [rb for rb, _ in done]
    return model


class ToolEngine:
    """The controller's engine under a tool's semantics (eval, simulate): rows in, rows out.
    Under fuzzylite's semantics the file's settings apply as in `Chain` (the rule base's
    locked inputs clamped, the file's resolution unless the semantics names one, a NaN output
    replaced by a numeric default, locked outputs clipped)."""

    def __init__(self, rb: RuleBase, semantics: str, settings: FileSettings | None = None):
        self.rb = rb
        self.name, self.resolution = parse_semantics(semantics)
        fuzzylite = self.name in ("fuzzylite", "pyfuzzylite")
        self.settings = settings if settings is not None and fuzzylite else FileSettings()
        if fuzzylite:
            self.rb = rb = fuzzylite_flat(rb, self.settings.flat)
        if self.resolution is None:        # each output its own (the file's, or the tool's)
            self.resolution = [self.settings.resolution.get(v.name) for v in rb.outputs]
        self.locked = np.array([v.name in self.settings.locked for v in rb.inputs], dtype=bool)
        self.lo = np.array([v.lo for v in rb.inputs], dtype=float)
        self.hi = np.array([v.hi for v in rb.inputs], dtype=float)

    def evaluate_rows(self, xt: np.ndarray, held: Held | None = None) -> np.ndarray:
        x = np.asarray(xt, dtype=float).T
        if self.locked.any():
            x = np.where(self.locked, np.clip(x, self.lo, self.hi), x)
        y = evaluate_as(self.rb, x, self.name, self.resolution, held)
        if self.settings.known or self.settings.locked:
            y = _as_fuzzylite_outputs(self.rb.outputs, y, self.settings,
                                      _silent(self.rb, x, self.name))
        return y.T


@dataclass
class FileSettings:
    """What a fuzzylite file says that the model does not carry (fuzzylite's OutputVariable
    and InputVariable, pyfuzzylite 8's variable.py): each variable's `lock-range` (inputs
    clamped to the range before the rules, outputs clipped after the default), each output's
    sampling resolution (FLL `Centroid 500`) and whether its default is `nan` (a numeric
    default replaces a NaN output: no rule fired, or an empty fuzzy set).  `flat`: the outputs
    of a hybrid FIS whose Constant terms fuzzylite 6 reads as memberships flat over the range
    under the file's DefuzzMethod (`fuzzylite_flat`)."""
    locked: set[str] = field(default_factory=set)
    resolution: dict[str, int] = field(default_factory=dict)
    nan_default: set[str] = field(default_factory=set)
    known: bool = False       # read from an FLL or FCL file (other files: NaN stays NaN)
    flat: set[str] = field(default_factory=set)


FLL_SECTION = re.compile(r"^\s*(InputVariable|OutputVariable|RuleBlock|Engine)\s*:\s*(\S*)")
FLL_SETTING = re.compile(r"^\s*(lock-range|defuzzifier|default)\s*:\s*(\S+)\s*(\S*)")
FCL_OUTPUT = re.compile(r"DEFUZZIFY\s+(\w+)(.*?)END_DEFUZZIFY", re.S | re.I)
FIS_HYBRID = re.compile(r"^\s*Type\s*=\s*'?hybrid\b", re.M | re.I)


def file_settings(model: Model) -> FileSettings:
    """The settings of the FLL or FCL file the model was imported from, or that a .fz file's
    `fuzzylite` statements say (`Model.fuzzylite`, written by `convert`); none for others."""
    if model.fuzzylite is not None:
        said = model.fuzzylite
        return FileSettings(set(said["locked"]), dict(said["resolution"]),
                            set(said["nan_default"]), bool(said["known"]),
                            set(said.get("flat", ())))
    text, path = model.source_text or "", (model.source_path or "").lower()
    found = FileSettings(known=path.endswith(".fll") or ".fcl" in path)
    if path.endswith(".fis") and FIS_HYBRID.search(text):
        # the outputs formats.fis read with the weighted average: all their terms constants
        found.flat = {v.name for rb in model.blocks for v in rb.outputs
                      if v.n_terms and np.all(v.kinds == TermKind.SINGLETON)}
    if path.endswith(".fll"):
        name = ""
        for line in text.splitlines():
            line = line.split("#", 1)[0]
            section, setting = FLL_SECTION.match(line), FLL_SETTING.match(line)
            if section:
                name = section.group(2) if section.group(1).endswith("Variable") else ""
            elif setting and name:
                key, value, extra = setting.groups()
                if key == "lock-range" and value == "true":
                    found.locked.add(name)
                elif key == "defuzzifier" and extra.isdigit():
                    found.resolution[name] = int(extra)
                elif key == "default" and value.lower() == "nan":
                    found.nan_default.add(name)
    elif ".fcl" in path:
        for name, body in FCL_OUTPUT.findall(text):
            if re.search(r"LOCK\s*:[^;]*RANGE", body, re.I):
                found.locked.add(name)
            if re.search(r"DEFAULT\s*:=\s*nan", body, re.I):
                found.nan_default.add(name)
    return found


def clamped_inputs(model: Model, semantics: str) -> set[str]:
    """The inputs `semantics` clamps to their ranges: the file's `lock-range` ones under
    fuzzylite's semantics, none otherwise."""
    if parse_semantics(semantics)[0] not in ("fuzzylite", "pyfuzzylite"):
        return set()
    return file_settings(model).locked


class Chain:
    """A model's rule blocks in order as one function of its inputs (the signals an imported
    model reads) to every block's outputs: `inputs`, `outputs` and `evaluate` under a
    semantics (a chained fuzzylite engine: one block reads another's output).  Under
    fuzzylite's semantics the file's settings apply (FileSettings)."""

    def __init__(self, model: Model):
        self.blocks = model.blocks
        self.inputs = model.blocks[0].inputs if len(model.blocks) == 1 else model.signals
        self.outputs = [v for rb in model.blocks for v in rb.outputs]
        self.settings = file_settings(model)

    def evaluate(self, x: np.ndarray, semantics: str = "exact",
                 resolution: dict[str, int] | None = None) -> np.ndarray:
        """x (N, I) -> (N, O) under `semantics`; `resolution`: an output's own sampling
        resolution, else the file's, else the tool's default (each output its own)."""
        x = np.atleast_2d(np.asarray(x, dtype=float))
        semantics, points = parse_semantics(semantics)      # NAME:N samples every output at N
        fuzzylite = semantics in ("fuzzylite", "pyfuzzylite")
        settings = self.settings if fuzzylite else FileSettings()
        every = {v.name: points for v in self.outputs} if points else {}
        resolution = {**settings.resolution, **every, **(resolution or {})}
        env = {v.name: np.clip(x[:, i], v.lo, v.hi) if v.name in settings.locked
               else x[:, i] for i, v in enumerate(self.inputs)}
        written: set[str] = set()
        for rb in self.blocks:
            if fuzzylite:
                rb = reading_activations(fuzzylite_flat(rb, settings.flat), written)
            xb = np.column_stack([env[v.name] for v in rb.inputs])
            # the rows are one controller's successive samples (fuzzylite's -d inputs.fld)
            y = evaluate_as(rb, xb, semantics, [resolution.get(v.name) for v in rb.outputs],
                            Held(sequence=True))
            if fuzzylite:
                y = _as_fuzzylite_outputs(rb.outputs, y, settings, _silent(rb, xb, semantics))
            env.update({v.name: y[:, o] for o, v in enumerate(rb.outputs)})
            env.update(term_activations(rb, xb))
            written.update(v.name for v in rb.outputs)
        return np.column_stack([env[v.name] for v in self.outputs])


def _as_fuzzylite_outputs(outputs: list[Variable], y: np.ndarray, settings: FileSettings,
                          silent: np.ndarray | None = None) -> np.ndarray:
    """pyfuzzylite 8's OutputVariable.defuzzify after the defuzzifier: a NaN becomes the
    default unless that is nan, then lock-range clips to the range.  `silent` (N, O): where no
    rule concluding the output fired; given, only there does the default replace a NaN
    (fuzzylite 6's OutputVariable::defuzzify takes the default where its fuzzy output is
    empty, and keeps the NaN a defuzzifier gives for a fired set that is 0 throughout: a
    BoundedDifference implication, say)."""
    y = y.copy()
    for o, var in enumerate(outputs):
        if settings.known and var.name not in settings.nan_default:
            nan = np.isnan(y[:, o]) if silent is None else np.isnan(y[:, o]) & silent[:, o]
            y[:, o] = np.where(nan, var.default, y[:, o])
        if var.name in settings.locked:
            y[:, o] = np.clip(y[:, o], var.lo, var.hi)
    return y


def _silent(rb: RuleBase, x: np.ndarray, semantics: str) -> np.ndarray | None:
    """Under fuzzylite 6's semantics (N, O): where no rule concluding the output fires (its
    activations within 1e-6 of 0, fuzzylite6_activations); None under pyfuzzylite 8's, whose
    default replaces every NaN."""
    if semantics != "fuzzylite":
        return None
    return ~fired(fuzzylite_hedges(rb), x, fuzzylite6_activations)


IDENTITY = (0.0, 1.0, np.inf, np.inf)     # a trapezoid whose membership is x on [0, 1]


def term_activations(rb: RuleBase, x: np.ndarray) -> dict[str, np.ndarray]:
    """`OUTPUT.TERM` -> (N,): the term's activation in the output's fuzzy set, the rules
    concluding it aggregated (fuzzylite's Aggregated::activationDegree: the s-norm of the
    aggregation, the plain sum without one)."""
    act = activations(rb, x)
    out = {}
    for o, var in enumerate(rb.outputs):
        snorm = aggregation_snorm(rb.inference_of(o).aggregation)
        for t, name in enumerate(var.names):
            rules = [act[:, r] for r in np.flatnonzero(rb.consequents[:, o] == t)]
            out[f"{var.name}.{name}"] = (np.zeros(x.shape[0]) if not rules else
                                         np.sum(rules, axis=0) if snorm is None else
                                         combine(rules, snorm, False))
    return out


def reading_activations(rb: RuleBase, outputs: set[str]) -> RuleBase:
    """fuzzylite's chained engines read `V is t` of an output V as t's activation in V's fuzzy
    set (term_activations), not as t's membership of V's value: the rule base with each such
    clause on an input `V.t` (that activation) through the identity term on [0, 1]."""
    columns, inputs = [], []       # per new input: the old column and the term it stands for
    for i, var in enumerate(rb.inputs):
        if var.name not in outputs:
            columns.append((i, None))
            inputs.append(var)
            continue
        for t, name in enumerate(var.names):
            columns.append((i, t))
            inputs.append(Variable(f"{var.name}.{name}", 0.0, 1.0, [name],
                                   np.array([int(TermKind.TRAPEZOID)]), np.array([IDENTITY])))
    if len(inputs) == len(rb.inputs):
        return rb
    new_of = {(i, t): k for k, (i, t) in enumerate(columns)}
    keep = [np.ones(rb.n_rules, bool) if t is None else rb.antecedents[:, i] == t
            for i, t in columns]
    cols = [i for i, _ in columns]
    ante = np.where(np.column_stack(keep), rb.antecedents[:, cols], -1)
    ante = np.where((ante >= 0) & np.array([t is not None for _, t in columns]), 0, ante)
    conditions = {}
    for r, program in rb.conditions.items():
        steps = program.copy()
        for step in steps:
            if step[0] == CondOp.CLAUSE and (int(step[1]), int(step[2])) in new_of:
                step[1], step[2] = new_of[int(step[1]), int(step[2])], 0
            elif step[0] == CondOp.CLAUSE:
                step[1] = new_of.get((int(step[1]), None), new_of.get((int(step[1]), 0)))
        conditions[r] = steps
    keep = np.column_stack(keep)
    return replace(rb, inputs=inputs, antecedents=ante, conditions=conditions,
                   negated=rb.negated[:, cols] & keep,
                   hedges=np.where(keep, rb.hedges[:, cols], Hedge.NONE))


def fuzzylite_hedges(rb: RuleBase) -> RuleBase:
    """The rule base as fuzzylite reads a FIS file's hedges: `extremely` is its S-curve
    (SHARPLY; a FIS `.3` is x^3, EXTREMELY, in the Octave toolkit), and a hedge said on a
    conclusion (CondOp.CONCLUDED) acts on the rule's activation and carries on to the
    conclusions after it (fuzzylite's Consequent::modify, as its FLL rules say): every such
    step, the rule's own and the earlier ones, is a plain HEDGE step."""
    programs = {}
    for r, p in rb.conditions.items():
        p = p.copy()
        concluded = p[:, 0] == CondOp.CONCLUDED
        p[concluded, 0], p[concluded, 2] = CondOp.HEDGE, 0
        p[:, 3] = np.where(p[:, 3] == Hedge.EXTREMELY, Hedge.SHARPLY, p[:, 3])
        programs[r] = p
    return replace(rb, hedges=np.where(rb.hedges == Hedge.EXTREMELY, Hedge.SHARPLY, rb.hedges),
                   conditions=programs)


def fuzzylite_flat(rb: RuleBase, flat: set[str]) -> RuleBase:
    """The rule base as fuzzylite 6 reads a hybrid FIS (its FisImporter: one DefuzzMethod):
    each output named in `flat` follows the block's aggregation and defuzzifier, and its
    Constant terms are memberships equal to the constant over the whole range (fuzzylite's
    Constant::membership; measured, tipper.fis: tsTip = 15, the middle of [0, 30], wherever a
    rule fires).  A FUNCTION term of the constant is that membership (fuzzyc.semantics.model)."""
    names = [v.name for v in rb.outputs if v.name in flat]
    if not names:
        return rb
    outputs = []
    for var in rb.outputs:
        if var.name in names:
            singles = np.flatnonzero(var.kinds == TermKind.SINGLETON)
            constants = {int(t): Formula(repr(float(var.params[t, 0])),
                                         ("num", float(var.params[t, 0]))) for t in singles}
            kinds = np.where(var.kinds == TermKind.SINGLETON, TermKind.FUNCTION, var.kinds)
            var = replace(var, kinds=kinds, formulas={**(var.formulas or {}), **constants})
        outputs.append(var)
    choices = {k: v for k, v in rb.output_choices.items() if k not in names}
    return replace(rb, outputs=outputs, output_choices=choices)


def resolutions(rb: RuleBase, resolution: int | Sequence[int | None] | None,
                default: int) -> list[int]:
    """Per output of rb its sampling resolution: `resolution` for all, or per output (None:
    `default`, the tool's own)."""
    if resolution is None or isinstance(resolution, (int, np.integer)):
        return [int(resolution or default)] * len(rb.outputs)
    return [int(r or default) for r in resolution]


def linear_unclamped(rb: RuleBase) -> RuleBase:
    """The rule base as fuzzylite reads a Linear term: c0 + c.x at the inputs' values as they
    are (fuzzylite 6 Linear::membership, pyfuzzylite 8 Linear.membership: the variables'
    values; only an input's own `lock-range` clamps, which Chain and ToolEngine do first).
    fuzzyc's engine reads a Linear term's inputs clamped to their ranges (exact semantics; the
    Octave toolkit refuses inputs outside the range): here the inputs' ranges are opened, which
    only that clamp reads."""
    if not any(np.any(v.kinds == TermKind.LINEAR) for v in rb.outputs):
        return rb
    return replace(rb, inputs=[replace(v, lo=-np.inf, hi=np.inf) for v in rb.inputs])


def evaluate_as(rb: RuleBase, x: np.ndarray, semantics: str = "exact",
                resolution: int | Sequence[int | None] | None = None,
                held: Held | None = None) -> np.ndarray:
    """x (N, I) -> y (N, O) as `semantics` computes it; `resolution` is fuzzylite's (the file's
    `Centroid 200`), one for all outputs or one per output (None: the tool's own);
    `held`: the held outputs (fuzzyc.engine.held_outputs)."""
    if semantics == "exact":
        return evaluate(rb, x, held=held)
    if semantics in ("fuzzylite", "pyfuzzylite"):
        resolution = resolutions(rb, resolution, RESOLUTION[semantics])
        rb = linear_unclamped(fuzzylite_hedges(rb))
        acts = fuzzylite6_activations if semantics == "fuzzylite" else pyfuzzylite_activations
        # Tsukamoto outputs by the tool's inverses; an output of its own (FCL's METHOD, FLL's
        # defuzzifier per output) too, beside outputs of other defuzzifiers
        inverted = [o for o in range(len(rb.outputs))
                    if rb.inference_of(o).defuzzifier in TSUKAMOTOS]
        if inverted:
            y = _tsukamoto(rb, np.atleast_2d(np.asarray(x, dtype=float)),
                           _fuzzylite6_inverse if semantics == "fuzzylite" else _exact_inverse,
                           acts, grouped=semantics == "pyfuzzylite")
            if len(inverted) == len(rb.outputs):
                return y
            others = evaluate_as(_not_inverted(rb), x, semantics, resolution, held)
            others[:, inverted] = y[:, inverted]
            return others
        if semantics == "fuzzylite" and _any_center_of_area(rb):
            rb = _over_rules(rb)
        if reads_values(rb):
            return _in_order(rb, x, semantics, resolution, held)
        y = evaluate_sampled(rb, x, resolution, first_plateau=semantics == "fuzzylite",
                             activations=acts)
        if semantics == "pyfuzzylite":
            y = _vanishing(rb, np.atleast_2d(np.asarray(x, dtype=float)), y)
        else:   # its norms, and its 1e-6 firing test, which the engine's floor is not
            y = _peaks_from(rb, np.atleast_2d(np.asarray(x, dtype=float)), y, acts)
        return np.where(fired(rb, x, acts), y, np.nan)
    if semantics == "octave":
        rb = octave_dsigmf(rb)
    if semantics == "octave" and rb.inference.defuzzifier in (Defuzzifier.WEIGHTED_AVERAGE,
                                                              Defuzzifier.WEIGHTED_SUM):
        return _grouped_average(rb, x, octave_activations(rb, x))
    if semantics in ("octave", "matlab"):
        octave = semantics == "octave"
        if octave:          # a Mamdani consequent's hedge: the term's membership ^ p
            from .octave_hedges import octave_mamdani_hedges
            rb = octave_mamdani_hedges(rb)
        return evaluate_sampled(rb, x, resolutions(rb, resolution, OCTAVE_POINTS),
                                Sampling.TRAPEZOID, methods=OCTAVE_SAMPLED + (
                                    (Defuzzifier.BISECTOR,) if octave else ()),
                                octave=octave, activations=octave_activations if octave
                                else activations)
    raise ValueError(f"unknown semantics `{semantics}`: one of {', '.join(SEMANTICS)}")


def _in_order(rb: RuleBase, x: np.ndarray, semantics: str, resolution: list[int],
              held: Held | None) -> np.ndarray:
    """A rule base whose outputs are evaluated in order (fuzzyc.engine.held_outputs) under fuzzylite's
    policy; its sampled outputs (which no formula reads and which hold nothing) resampled."""
    y = evaluate(rb, x, held=held, policy=POLICIES[semantics])
    read = {n for v in rb.outputs for f in (v.formulas or {}).values() for n in f.names()}
    sampled = [o for o, v in enumerate(rb.outputs) if rb.inference_of(o).defuzzifier in SAMPLED]
    for o in sampled:
        var = rb.outputs[o]
        if var.lock_previous or var.name in read:
            raise FuzzycError([Diagnostic(var.loc, f"`{var.name}` is sampled ({semantics}'s "
                                                   f"{rb.inference_of(o).defuzzifier.name.lower()}"
                                                   ") and holds its value or is read by a "
                                                   "Function term: not reproduced yet")])
    if sampled:
        stateless = replace(rb, outputs=[replace(v, lock_previous=False) for v in rb.outputs])
        again = evaluate_sampled(stateless, x, resolution,
                                 first_plateau=semantics == "fuzzylite")
        y[:, sampled] = np.where(fired(rb, x)[:, sampled], again[:, sampled], np.nan)
    return y


TSUKAMOTOS = (Defuzzifier.TSUKAMOTO, Defuzzifier.TSUKAMOTO_SUM)
SUMMED = (Defuzzifier.WEIGHTED_SUM, Defuzzifier.GROUPED_SUM)


def pyfuzzylite_activations(rb: RuleBase, x: np.ndarray) -> np.ndarray:
    """The rules' activations as pyfuzzylite 8 uses them: every activation above 0 counts
    (no ACTIVATION_FLOOR; Rule.trigger keeps any degree), after the weights."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    mus = [memberships(var, x[:, i]) for i, var in enumerate(rb.inputs)]
    act = flat_activations(rb, mus, mus, x.shape[0])
    for r, program in rb.conditions.items():
        act[:, r] = run_condition(rb, program, x)
    return act * rb.weights


def _vanishing(rb: RuleBase, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """y with the peak-based outputs recomputed where every rule concluding them fires below
    the engine's ACTIVATION_FLOOR but above 0 (pyfuzzylite 8 defuzzifies there: a weighted
    average of activations of 1e-20 is the average of the values).  There the rules' weights
    are scaled so that the largest activation is 1: a weighted average and a grouped maximum
    do not change, a weighted sum is divided back by the scale."""
    raw = pyfuzzylite_activations(rb, x)
    kept = firing(raw)
    for o in range(len(rb.outputs)):
        method = rb.inference_of(o).defuzzifier
        if method not in (Defuzzifier.WEIGHTED_AVERAGE, Defuzzifier.CENTER_OF_AREA, *SUMMED):
            continue
        concluding = rb.consequents[:, o] >= 0
        lost = (raw[:, concluding] > 0).any(axis=1) & ~(kept[:, concluding] > 0).any(axis=1)
        for row in np.flatnonzero(lost):
            scale = 1.0 / raw[row, concluding].max()
            value = evaluate(replace(rb, weights=rb.weights * scale), x[row:row + 1])[0, o]
            y[row, o] = value / scale if method in SUMMED else value
    return y


def _not_inverted(rb: RuleBase) -> RuleBase:
    """rb with its Tsukamoto outputs read as weighted averages (their columns are replaced by
    `_tsukamoto`'s): what the other outputs need of the rule base, and no Tsukamoto left."""
    wa = Defuzzifier.WEIGHTED_AVERAGE
    inference = rb.inference if rb.inference.defuzzifier not in TSUKAMOTOS else \
        replace(rb.inference, defuzzifier=wa)
    choices = {name: (agg, wa if d in TSUKAMOTOS else d)
               for name, (agg, d) in rb.output_choices.items()}
    return replace(rb, inference=inference, output_choices=choices)


def _tsukamoto(rb: RuleBase, x: np.ndarray, inverse, acts=activations,
               grouped: bool = False) -> np.ndarray:
    """sum act_r z_r / sum act_r over the firing rules (TSUKAMOTO_SUM: sum act_r z_r),
    z_r = inverse(kinds, params, act_r) (fuzzylite's, unclipped); NaN where none fires.
    `grouped` (pyfuzzylite 8's Aggregated.grouped_terms): first the activations of each term's
    rules folded with the output's aggregation (a sum for none), one item per term."""
    act = acts(rb, x)
    y = np.full((x.shape[0], len(rb.outputs)), np.nan)
    everyone = act
    for o, var in enumerate(rb.outputs):
        act, J = everyone, rb.consequents[:, o]
        summed = rb.inference_of(o).defuzzifier == Defuzzifier.TSUKAMOTO_SUM
        if grouped:
            act, J = _grouped_terms(act, J, var.n_terms, rb.inference_of(o).aggregation)
        # pyfuzzylite 8 keeps every concluded term, at degree 0 too (Consequent.modify appends
        # each rule's): 0 times an infinite value (a Sigmoid's or Concave's at 0) is NaN there
        firing = (J >= 0) & ((act > 0) | grouped)
        t = J.clip(0)
        params = np.broadcast_to(np.asarray(var.params, dtype=float)[t], act.shape + (4,))
        with np.errstate(invalid="ignore", divide="ignore"):
            z = inverse(np.broadcast_to(var.kinds[t], act.shape), params,
                        np.where(firing, act, 0.5), var.lo, var.hi)
            if grouped:      # pyfuzzylite's WeightedSum: (sum w z / sum w) * sum w
                num = np.where(firing, act * z, 0.0).sum(axis=1)
                den = np.where(firing, act, 0.0).sum(axis=1)
                y[:, o] = num / den * (den if summed else 1.0)
                continue
            num = np.where(firing, act * z, 0.0).sum(axis=1)
            den = np.where(firing, act, 0.0).sum(axis=1)
            y[:, o] = np.where(den > 0, num if summed else num / np.where(den > 0, den, 1.0),
                               np.nan)
    return y


def _grouped_terms(act: np.ndarray, J: np.ndarray, n_terms: int,
                   aggregation: Aggregation) -> tuple[np.ndarray, np.ndarray]:
    """(alpha (N, T), term ids (T,)): each term's activations over the rules concluding it,
    folded with the aggregation's s-norm (SUM: added), -1 for a term no rule concludes."""
    snorm = aggregation_snorm(aggregation)
    alpha = np.zeros((act.shape[0], n_terms))
    ids = np.full(n_terms, -1)
    for t in range(n_terms):
        rules = np.flatnonzero(J == t)
        if rules.size:
            ids[t] = t
            alpha[:, t] = act[:, rules].sum(axis=1) if snorm is None else \
                combine([act[:, r] for r in rules], snorm, False)
    return alpha, ids


def _exact_inverse(kinds, params, w, lo, hi) -> np.ndarray:
    """pyfuzzylite 8: its own formulas (term.py, each monotonic term's `tsukamoto`), not
    clipped to the range [lo, hi]: exact inverses in (0, 1]; a term's rules grouped by a sum
    may pass 1, where the formulas carry on (Ramp, Concave: past the end) or give NaN (Sigmoid,
    SShape, ZShape: the log or square root of a negative number), as pyfuzzylite does."""
    a, b, c, d = np.moveaxis(np.asarray(params, dtype=float), -1, 0)
    z = term_inverse(kinds, params, np.clip(w, 0.0, 1.0))
    with np.errstate(invalid="ignore", divide="ignore"):
        rising = np.isfinite(a) & np.isfinite(b)            # a Ramp: trapezoid shoulders
        start, end = np.where(rising, a, d), np.where(rising, b, c)
        ramp = start + (end - start) * w
        concave = (a - b) / w + 2 * b - a                   # (inflection, end)
        sigmoid = a + np.log(1.0 / w - 1.0) / -b            # (inflection, slope)
        low = w <= 0.5
        s_shape = np.where(low, a + (b - a) * np.sqrt(w / 2), b - (b - a) * np.sqrt((1 - w) / 2))
        z_shape = np.where(low, b - (b - a) * np.sqrt(w / 2), a + (b - a) * np.sqrt((1 - w) / 2))
    for kind, value in ((TermKind.TRAPEZOID, ramp), (TermKind.CONCAVE, concave),
                        (TermKind.SIGMOID, sigmoid), (TermKind.SSHAPE, s_shape),
                        (TermKind.ZSHAPE, z_shape)):
        z = np.where(kinds == kind, value, z)
    return z


def _fuzzylite6_inverse(kinds, params, w, lo, hi) -> np.ndarray:
    a, b = params[..., 0], params[..., 1]
    z = term_inverse(kinds, params, w)
    up = b >= 0
    sigmoid = kinds == TermKind.SIGMOID
    z = np.where(sigmoid & (np.abs(w - 1) < FL_EPSILON), np.where(up, hi, lo),
                 np.where(sigmoid & (np.abs(w) < FL_EPSILON),
                          np.where(up, lo, hi), z))
    d = b - a
    for kind, first, second in ((TermKind.SSHAPE, a + np.sqrt(0.5 * w) * np.abs(d),
                                 b + np.sqrt(0.5 * (1 - w)) * np.abs(d)),
                                (TermKind.ZSHAPE, a + np.sqrt(0.5 * (1 - w)) * np.abs(d),
                                 b + np.sqrt(0.5 * w) * np.abs(d))):
        mu = [pointwise(kind, params, c) for c in (first, second)]
        pick = np.where(np.abs(w - mu[0]) < np.abs(w - mu[1]), first, second)
        z = np.where(kinds == kind, pick, z)
    # Concave: inverted at its own membership of w, reaching 1 within 1e-6 of its end
    at_end = np.abs(w - b) < FL_EPSILON
    mu = np.where(at_end, 1.0, pointwise(TermKind.CONCAVE, params, w))
    return np.where(kinds == TermKind.CONCAVE, term_inverse(kinds, params, mu), z)


def _grouped_average(rb: RuleBase, x: np.ndarray, act: np.ndarray | None = None) -> np.ndarray:
    """The Octave toolkit's Sugeno output (aggregate_output_sugeno.m, defuzz.m): per term, the
    rules' strengths merged with the aggregation (a sum for `sum`); then wtaver
    sum alpha_j z_j / sum alpha_j (the output's default when all are 0: the toolkit fails
    there) or wtsum sum alpha_j z_j.  `act`: the rules' activations (default the engine's)."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    act = activations(rb, x) if act is None else act
    y = np.empty((x.shape[0], len(rb.outputs)))
    snorm = aggregation_snorm(rb.inference.aggregation)
    for o, var in enumerate(rb.outputs):
        z = _term_values(var, x)
        alpha = np.zeros_like(z)
        for t in range(var.n_terms):
            rules = np.flatnonzero(rb.consequents[:, o] == t)
            if rules.size:
                alpha[:, t] = act[:, rules].sum(axis=1) if snorm is None else \
                    combine([act[:, r] for r in rules], snorm, False)
        total = alpha.sum(axis=1)
        if rb.inference_of(o).defuzzifier == Defuzzifier.WEIGHTED_SUM:
            y[:, o] = (alpha * z).sum(axis=1)
            continue
        y[:, o] = np.where(total > 0, (alpha * z).sum(axis=1) / np.where(total > 0, total, 1.0),
                           var.default)
    return y


def octave_activations(rb: RuleBase, x: np.ndarray) -> np.ndarray:
    """`_octave_strengths`, and a rule whose program ends in a negated conclusion (a FIS
    Sugeno row's `-t`: its CONCLUDED step, then NOT) 0 where its strength before the negation
    is 0: eval_rules_sugeno.m computes a rule's height (1 - strength^(1/p)) only where its
    firing strength is not 0, so a rule that does not fire adds nothing, not a height of 1."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    act = _octave_strengths(rb, x)
    for r, program in rb.conditions.items():
        if len(program) > 1 and program[-1, 0] == CondOp.NOT and \
                program[-2, 0] == CondOp.CONCLUDED and program[-2, 2]:
            before = _octave_strengths(replace(rb, conditions={r: program[:-1]}), x)[:, r]
            act[:, r] = np.where(before == 0.0, 0.0, act[:, r])
    return act


def _octave_strengths(rb: RuleBase, x: np.ndarray) -> np.ndarray:
    """The rules' activations as the Octave toolkit computes them (eval_firing_strength.m):
    the AND or OR method applied to the vector of the rule's clauses at once, so
    drastic_product is min(clauses) where max(clauses) is 1, else 0, and drastic_sum
    max(clauses) where min(clauses) is 0, else 1 -- not the pairwise folds, which differ from
    three clauses on; the other methods fold as the engine does.  Every activation above 0
    counts (the toolkit skips a rule only where its strength is 0: no ACTIVATION_FLOOR)."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    act = pyfuzzylite_activations(rb, x)
    drastic_and = rb.inference.and_ == TNorm.DRASTIC_PRODUCT
    drastic_or = rb.inference.or_ == SNorm.DRASTIC_SUM
    if not (drastic_and or drastic_or):
        return act
    mus = [memberships(var, x[:, i]) for i, var in enumerate(rb.inputs)]
    n = x.shape[0]

    def truth(connective: Connective, norm) -> np.ndarray:
        # every rule's clauses combined by min or max (absent clauses are neutral there)
        plain = replace(rb, connective=np.full(rb.n_rules, int(connective)),
                        inference=replace(rb.inference, and_=norm, or_=norm))
        return flat_activations(plain, mus, mus, n)

    lowest, highest = truth(Connective.AND, TNorm.MIN), truth(Connective.OR, SNorm.MAX)
    conj = rb.connective == Connective.AND
    nary = np.where(conj, np.where(highest == 1.0, lowest, 0.0) if drastic_and else np.nan,
                    np.where(lowest == 0.0, highest, 1.0) if drastic_or else np.nan)
    use = (conj & drastic_and) | (~conj & drastic_or)
    for r, program in rb.conditions.items():     # hedged clauses or conclusions
        use[r] = False
        ops = set(program[:, 0].tolist())      # the row's connective is its program's
        and_ = CondOp.AND in ops or (CondOp.OR not in ops and bool(conj[r]))
        if (drastic_and and and_) or (drastic_or and not and_):
            act[:, r] = _octave_program(rb, program, x, and_) * rb.weights[r]
    return np.where(use, nary * rb.weights, act)


def octave_dsigmf(rb: RuleBase) -> RuleBase:
    """The rule base with its dsigmf terms as the Octave toolkit computes them: dsigmf.m is
    max(0, min(1, sig1 - sig2)), the difference clipped, where fuzzyc's SigmoidDifference (a
    FIS dsigmf is read so) is |sig1 - sig2|, fuzzylite's: they differ where the second sigmoid
    is above the first.  Each such term becomes a Function term of that formula (built here
    from the term's numbers, never from file text)."""
    def clipped(var: Variable) -> Variable:
        kinds = np.asarray(var.kinds)
        where = np.flatnonzero(kinds == TermKind.SIGMOID_DIFFERENCE)
        if not where.size:
            return var
        formulas = dict(var.formulas or {})
        for t in where:
            c1, a1, a2, c2 = (repr(float(v)) for v in np.asarray(var.params, dtype=float)[t])
            formulas[int(t)] = parse_formula(
                f"max(0, min(1, 1 / (1 + exp(-({a1}) * (x - ({c1})))) "
                f"- 1 / (1 + exp(-({a2}) * (x - ({c2}))))))")
        kinds = np.where(kinds == TermKind.SIGMOID_DIFFERENCE, int(TermKind.FUNCTION), kinds)
        return replace(var, kinds=kinds, formulas=formulas)

    if not any(np.any(np.asarray(v.kinds) == TermKind.SIGMOID_DIFFERENCE)
               for v in rb.inputs + rb.outputs):
        return rb
    return replace(rb, inputs=[clipped(v) for v in rb.inputs],
                   outputs=[clipped(v) for v in rb.outputs])


def _octave_nary(values: list[np.ndarray], conj: bool) -> np.ndarray:
    """drastic_product.m / drastic_sum.m over a rule's clause truths at once."""
    v = np.array(values)
    if conj:
        return np.where(v.max(axis=0) == 1.0, v.min(axis=0), 0.0)
    return np.where(v.min(axis=0) == 0.0, v.max(axis=0), 1.0)


def _octave_program(rb: RuleBase, program: np.ndarray, x: np.ndarray, conj: bool) -> np.ndarray:
    """A FIS row's clause program (engine.inference.run_condition: its clauses with their
    hedges and NOT, joined by the row's one connective, then a hedge on its conclusion) with
    the connective taken over all the clauses at once (`_octave_nary`)."""
    stack: list[list[np.ndarray]] = []
    for step in program:
        op, i, t, h = (int(v) for v in step)
        if op in (CondOp.AND, CondOp.OR):
            b, a = stack.pop(), stack.pop()
            stack.append(a + b)
            continue
        if op == CondOp.CLAUSE:
            stack.append([run_condition(rb, step[None], x)])
            continue
        top = stack.pop()       # NOT and a hedge act on one clause, CONCLUDED on the row's
        value = top[0] if len(top) == 1 and op != CondOp.CONCLUDED else _octave_nary(top, conj)
        if op == CondOp.NOT:
            value = 1.0 - value
        elif op == CondOp.HEDGE:
            value = apply_hedges(value[:, None], np.array([h]))[:, 0]
        elif op == CondOp.CONCLUDED and t:
            value = value ** (1.0 / HEDGE_EXPONENT[h])
        elif op == CondOp.WEIGHT:
            value = value * weight_of(t)
        stack.append([value])
    return _octave_nary(stack.pop(), conj)


def _term_values(var, x: np.ndarray) -> np.ndarray:
    """(N, T): each term's value z at the inputs (singletons: their value; linear: c0 + c.x)."""
    coefficients = linear_coefficients(var, x.shape[1])
    linear = coefficients[:, 0] + x @ coefficients[:, 1:].T
    return np.where(var.kinds == TermKind.LINEAR, linear, var.peaks())


def fuzzylite6_norms() -> tuple[dict, dict]:
    """(t-norms, s-norms) by enum as fuzzylite 6 computes them (engine.norms.combine)."""
    return {**T_NORMS, **FL6_T}, {**S_NORMS, **FL6_S}


def fuzzylite6_activations(rb: RuleBase, x: np.ndarray) -> np.ndarray:
    """The rules' activations as fuzzylite 6 triggers them: its norms (`fuzzylite6_norms`),
    and Rule::trigger fires a rule only where Op::isGt(activation, 0), which is false within its
    1e-6 (FL_EPSILON) of 0, so an activation below 1e-6 (or NaN) is 0: it adds nothing to the
    output's fuzzy set, and an output whose rules all stay below it takes its default
    (measured: the fuzzylite 6 CLI; pyfuzzylite 8 fires every rule above 0).  The test is on
    the weighted activation before the hedges of the rule's conclusion (Rule::trigger, then
    Consequent::modify): where a program ends in hedges over a WEIGHT step (a weight under a
    hedged conclusion), on the value at that step; the rule then adds its hedged activation,
    below 1e-6 or not."""
    x = np.atleast_2d(np.asarray(x, dtype=float))
    tables = fuzzylite6_norms()
    mus = [memberships(var, x[:, i]) for i, var in enumerate(rb.inputs)]
    with np.errstate(invalid="ignore", divide="ignore"):
        act = flat_activations(rb, mus, mus, x.shape[0], tables)
        for r, program in rb.conditions.items():
            act[:, r] = run_condition(rb, program, x, tables)
        act = act * rb.weights
        gate = act.copy()
        for r, program in rb.conditions.items():
            k = len(program)
            while k > 1 and program[k - 1, 0] == CondOp.HEDGE:
                k -= 1
            if k < len(program) and program[k - 1, 0] == CondOp.WEIGHT:
                gate[:, r] = run_condition(rb, program[:k], x, tables) * rb.weights[r]
    return np.where(gate >= FL_EPSILON, act, 0.0)


def _peaks_from(rb: RuleBase, x: np.ndarray, y: np.ndarray, acts) -> np.ndarray:
    """y with the peak-based outputs (weighted average, sum, center of area) computed from the
    tool's activations `acts` (the engine computes its own, the model's norms)."""
    from ..engine.defuzz import OutputDefuzzifier
    act = acts(rb, x)
    for o, var in enumerate(rb.outputs):
        inference = rb.inference_of(o)
        if inference.defuzzifier not in (Defuzzifier.WEIGHTED_AVERAGE,
                                         Defuzzifier.CENTER_OF_AREA, *SUMMED):
            continue
        y[:, o] = OutputDefuzzifier(var, inference, rb.inputs)(act, rb.consequents[:, o], x)
    return y


def fired(rb: RuleBase, x: np.ndarray, acts=activations) -> np.ndarray:
    """(N, O) bool: some rule concluding the output has a positive activation (`acts`: the
    rules' activations as the tool computes them)."""
    act = acts(rb, np.atleast_2d(np.asarray(x, dtype=float)))
    concludes = rb.consequents >= 0                       # (R, O)
    return (act > 0).astype(float) @ concludes.astype(float) > 0


__all__ = ["SEMANTICS", "ToolEngine", "evaluate_as", "exact_equivalent", "fired",
           "with_tool_semantics", "parse_semantics", "SAMPLED"]
