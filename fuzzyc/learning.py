"""Neuro-fuzzy learning of a weighted-sum rule base (Tarng, Hua, Huang, ch. 6, eqs. 6.22-6.25).

The controller's output `du = sum_j mu_j w_j` (eq. 6.19) has one learnable singleton w_j per
rule; the rule base starts empty (all w_j = 0) and the weights are learned over cutting cycles.
Each sample only the weight of the rule with the largest firing mu_j is changed (the chapter's
simplification), and the performance index of a cycle is (eq. 6.22)

    PI = 1/2 * sum_i (e(i)^2 + rho * cf(i)^2),   rho = 6, eta = 0.25.

Our reading of eq. 6.24. The printed equation, dw_j = eta * (-|grad PI|) * [e; cf] with
-|grad PI| = (-|e| - |cf|), is garbled: it multiplies a scalar by a vector to update a scalar,
and taken literally (-(|e|+|cf|) * e) it would lower the feed whenever the force is too low,
the opposite of the chapter's integral action. We read it as what its words say: one step of
gradient descent on PI for the winning weight,

    dw_j = -eta' * dPI_i/dw_j.

With e = GE (Fr - Fc), cf = GCF (Fc(i) - Fc(i-1)) and Fc rising with the feed U
(dFc/dU = J > 0, its size unknown to the controller), dFc/dw_j = J * GU * mu_j gives
dPI_i/dw_j = J GU mu_j (-GE e + rho GCF cf). The unknown positive factor J*GU*GE*mu_j goes into
the learning rate, which leaves

    dw_j = eta * (e - rho * (GCF/GE) * cf).        (our eq. 6.24)

It raises the winning weight when the force is below the reference and not rising, lowers it
when the force is above or climbing fast (the rho term damps the entry overshoot), and it
vanishes at the set point. `tests/test_learn_milling.py` shows PI falling over 15 cycles.
"""
from __future__ import annotations

import re
from dataclasses import dataclass, field
from types import ModuleType
from typing import Any

import numpy as np

from .engine.inference import activations
from .semantics.model import Defuzzifier, Model, TNorm


@dataclass
class Learner:
    """The learning rule bound to one model: which output it trains and with which gains."""
    model: Model
    output: str = "du"
    error: str = "e"
    change: str = "cf"
    eta: float = 0.25
    rho: float = 6.0
    change_weight: float = field(init=False)

    def __post_init__(self) -> None:
        rb = self.model.rulebase
        inference = rb.inference_of(rb.output_index(self.output))
        if inference.defuzzifier != Defuzzifier.WEIGHTED_SUM or inference.and_ != TNorm.PRODUCT:
            raise ValueError(f"{self.model.name}: neuro-fuzzy learning needs "
                             "`inference and = product, defuzzify = weighted_sum`")
        self.var = rb.outputs[rb.output_index(self.output)]
        if self.var.learnable is None or not self.var.learnable.any():
            raise ValueError(f"{self.model.name}: output `{self.output}` has no learnable terms")
        self.rule_term = rb.consequents[:, rb.output_index(self.output)]
        self.inputs = [rb.input_index(self.error), rb.input_index(self.change)]
        params = self.model.symbol_values()
        # rho * GCF/GE of our eq. 6.24; 1 when the file has no GE/GCF (e, cf already comparable)
        self.change_weight = self.rho * params.get("GCF", 1.0) / params.get("GE", 1.0)
        self.weights = self.var.params[:, 0].copy()

    def update(self, signals: dict[str, np.ndarray], learn: bool = True) -> np.ndarray:
        """One sample: this sample's PI terms (N,); with `learn`, the winning weight changes."""
        e = np.asarray(signals[self.error], float)
        cf = np.asarray(signals[self.change], float)
        pi = 0.5 * (e ** 2 + self.rho * cf ** 2)            # eq. 6.22, this sample's term
        if not learn:
            return pi
        x = np.zeros((e.shape[0], len(self.model.rulebase.inputs)))
        x[:, self.inputs[0]], x[:, self.inputs[1]] = e, cf
        winner = np.argmax(activations(self.model.rulebase, x), axis=1)
        step = self.eta * (e - self.change_weight * cf)
        # a batch shares one rule base: average the batch's votes per term
        votes = np.zeros_like(self.weights)
        np.add.at(votes, self.rule_term[winner], step / e.shape[0])
        learnable = self.var.learnable
        self.weights = np.where(learnable, np.clip(self.weights + votes, self.var.lo, self.var.hi),
                                self.weights)
        return pi


@dataclass
class CycleResult:
    pi: float
    time: float                 # s until the plant reported done (or the time limit)
    finished: bool
    trace: dict[str, np.ndarray]


def run_cycle(controller: Any, plant: ModuleType, params: Any, learner: Learner, learn: bool,
              max_time: float, period: float, rng: np.random.Generator | None = None
              ) -> CycleResult:
    """One cutting cycle of batch 1: PI of the cycle, learning on line when `learn`.

    Signals are wired by name: the plant's outputs feed the controller's inputs and the
    controller's outputs are the plant's inputs. The first measurement is the plant at rest.
    """
    controller.reset(1)
    state = plant.initial_state(params, 1, rng)
    measured = {name: np.zeros(1) for name in controller.input_names}
    pi, steps, finished = 0.0, int(np.ceil(max_time / period)), False
    trace: dict[str, list] = {}
    for i in range(steps):
        commands = controller.step(measured)
        pi += float(learner.update(controller.signals, learn)[0])
        if learn:
            controller.set_consequent_values(learner.output, learner.weights)
        state, outputs = plant.step(params, state, commands, i * period, period, rng)
        for name, value in {**commands, **outputs}.items():
            trace.setdefault(name, []).append(float(value[0]))
        measured = {name: outputs[name] for name in controller.input_names}
        if outputs.get("done", np.zeros(1))[0] > 0:
            finished = True
            break
    return CycleResult(pi, (i + 1) * period, finished, {k: np.array(v) for k, v in trace.items()})


@dataclass
class LearningResult:
    weights: np.ndarray          # the learned values of the output's terms (T,)
    pi: np.ndarray               # performance index per cycle
    cycles: list[CycleResult]


def learn(controller: Any, plant: ModuleType, params: Any, cycles: int, max_time: float,
          period: float | None = None, output: str = "du", eta: float = 0.25, rho: float = 6.0,
          rng: np.random.Generator | None = None) -> LearningResult:
    """Repeat the cutting cycle `cycles` times, learning on line; weights carry over.

    `controller` runs the model being trained (e.g. `fuzzyc.engine.chain.Controller`); its
    model's learnable values are the starting weights and end up as the learned ones.
    """
    model = controller.model
    period = period or model.period
    if period is None:
        raise ValueError(f"{model.name}: learning needs the controller's `period`")
    learner = Learner(model, output=output, eta=eta, rho=rho)
    results = [run_cycle(controller, plant, params, learner, True, max_time, period, rng)
               for _ in range(cycles)]
    return LearningResult(learner.weights.copy(), np.array([r.pi for r in results]), results)


def learn_scenario(scenario: Any, cycles: int, eta: float = 0.25, rho: float = 6.0,
                   output: str = "du") -> tuple[Any, LearningResult]:
    """Learn on a scenario (`fuzzyc.plants.scenario.Scenario`): its plant, params, rule base,
    controller settings, period and duration (the time limit of a cycle)."""
    from fuzzyc.runtime.simulate import load_controller

    controller = load_controller(scenario, batch=1)
    result = learn(controller, scenario.plant_module(), scenario.plant_params(), cycles,
                   scenario.duration, scenario.period, output, eta, rho)
    return controller, result


_TABLE = r"table\s+{name}\b[^{{]*\blearnable\s*\{{(?P<body>[^}}]*)\}}"
_NUMBER = re.compile(r"[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?")


# The first line of a learned rule file: learned weights are a result, never hand-written.
PROVENANCE = "# LEARNED WEIGHTS, written by"
_SET_LEARN = re.compile(r"^([ \t]*)(set[ \t]+learn\.\w+[ \t]*=[^\n#]*?)[ \t]*$", re.MULTILINE)
_HEADER = re.compile(r'^([ \t]*controller[ \t]+)(\w+)(?:([ \t]+)"([^"\\\n]*)")?', re.MULTILINE)
LEARNED_NAME, LEARNED_TITLE = "_learned", ", learned weights"


def _learned_header(match: re.Match) -> str:
    """The learned file is a controller of its own: `NAME_learned`, its title says so (the
    untrained and the learned one side by side get two C headers, plots and eval lines)."""
    start, name, space, title = match.groups()
    name = name if name.endswith(LEARNED_NAME) else name + LEARNED_NAME
    if title is None:
        return start + name
    title = title if title.endswith(LEARNED_TITLE) else title + LEARNED_TITLE
    return f'{start}{name}{space}"{title}"'


def provenance(file_name: str, scenario: str, cycles: int, eta: float, rho: float,
               pi: np.ndarray) -> str:
    """How a learned file was made: the command that remakes it, and the PI it reached."""
    return (f"`fuzzyc learn {file_name} --scenario {scenario} --cycles {cycles} --eta {eta:g} "
            f"--rho {rho:g}` ({pi[0]:.4g} -> {pi[-1]:.4g} performance index)")


def trained_text(model: Model, weights: np.ndarray, output: str = "du",
                 provenance: str = "") -> str:
    """The model's source with the learnable table's numbers replaced by `weights`, and
    `provenance` (how they were learned) as a first comment line, replacing an earlier one.

    Everything else (comments, layout, other statements) is kept; numbers in comments inside
    the table are left alone. The k-th number in the table body is the k-th learnable term
    (the builder creates them in cell order); the numbers are right-aligned to one width so the
    rows stay columns, and the result is parsed again and must give back these weights.
    """
    from .language.parser import parse

    text = model.source_text or ""
    match = re.search(_TABLE.format(name=re.escape(output)), text)
    if match is None:
        raise ValueError(f"{model.source_path}: no `table {output} ... learnable {{...}}` found")
    var = model.rulebase.outputs[model.rulebase.output_index(output)]
    written = [f"{w:.6g}" for w in np.asarray(weights, float)[var.learnable]]
    width = max(len(w) for w in written)
    lines = [line.partition("#") for line in match.group("body").split("\n")]
    if sum(len(_NUMBER.findall(code)) for code, _, _ in lines) != len(written):
        raise ValueError(f"{model.source_path}: the `{output}` table does not hold one number "
                         f"per learnable term ({len(written)})")
    values = iter(written)
    body = "\n".join(_NUMBER.sub(lambda _: next(values).rjust(width), code) + sep + comment
                     for code, sep, comment in lines)
    new_text = text[:match.start("body")] + body + text[match.end("body"):]
    if new_text.startswith(PROVENANCE):
        new_text = new_text.partition("\n")[2]
    if provenance:
        new_text = f"{PROVENANCE} {provenance}\n{new_text}"
        # a closed-loop property's `set learn.cycles = N` trains an untrained file first; the
        # learned file is checked as it is
        new_text = _SET_LEARN.sub(r"\1# \2   (already learned: the table above)", new_text)
        new_text = _HEADER.sub(_learned_header, new_text, count=1)
    check = parse(new_text, model.source_path or "<trained>")
    got = check.rulebase.outputs[check.rulebase.output_index(output)]
    if not np.array_equal(got.params[got.learnable, 0], np.array(written, float)):
        raise ValueError("the rewritten table does not read back as the learned weights")
    return new_text


def untrained_note(model: Model) -> str | None:
    """A warning for a model whose learnable terms all still hold 0 (as shipped, before
    `fuzzyc learn`): its output is 0 whatever the input, so its runs say nothing of the method."""
    for var in model.rulebase.outputs:
        if var.learnable is not None and var.learnable.any() \
                and not np.any(var.params[var.learnable, 0]):
            return (f"UNTRAINED: the {int(var.learnable.sum())} learnable weights of `{var.name}` "
                    f"are all 0 (train them with `fuzzyc learn`)")
    return None
