"""A Model's whole signal chain (steps, rule base, outputs) for a batch of independent loops.

Robustness to bad samples (a NaN or infinite raw input):
- stateful steps (delta, prev, lowpass) keep their last finite memory; their output for that
  sample is NaN when the argument is, so the rule base sees a NaN input;
- the rule base gives memberships 0 for NaN inputs, hence its defaults where nothing fires;
- an output whose expression is not finite for a sample holds its state: an INCREMENT or
  RECIPROCAL_INCREMENT treats a non-finite increment as 0, a DIRECT output keeps its last value
  (its `init` before the first finite one).  Outputs are therefore always finite.
`set_consequent_values` changes the rule base of the model in place (the learned parameters
belong to the model, so exporting it after learning writes the learned values).
"""
from __future__ import annotations

import numpy as np

from .engine import compiled
from .expr import evaluate_expr
from .model import Model, Op, OutputKind, TermKind


class Controller:
    def __init__(self, model: Model, batch: int = 1):
        self.model = model
        self.rulebase = model.rulebase
        self.input_names = [s.name for s in model.signals]
        self.output_names = [o.name for o in model.outputs]
        self.params = model.symbol_values()
        self.signals: dict[str, np.ndarray] = {}
        self.reset(batch)

    def reset(self, batch: int | None = None) -> None:
        """Forget all memories (steps and output states); optionally change the batch size."""
        if batch is not None:
            self.batch = int(batch)
        n = self.batch
        # NaN memory = "no sample yet"; only finite values are ever stored.
        self._memory = {s.name: np.full(n, np.nan) for s in self.model.steps if s.op != Op.ASSIGN}
        self._state = {o.name: np.full(n, self._initial_state(o)) for o in self.model.outputs}
        self.signals = {}

    @staticmethod
    def _initial_state(out) -> float:
        if out.kind == OutputKind.RECIPROCAL_INCREMENT:
            return 1.0 / out.init
        return float(out.init)

    def _column(self, value, n: int) -> np.ndarray:
        return np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy()

    def step(self, inputs: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """One sample for every loop: raw inputs (N,) each -> controller outputs (N,) each."""
        n = self.batch
        missing = [name for name in self.input_names if name not in inputs]
        if missing:
            raise KeyError(f"no value for input(s): {', '.join(missing)}")
        env: dict = dict(self.params)
        env.update({name: self._column(inputs[name], n) for name in self.input_names})
        for s in self.model.steps:
            env[s.name] = self._run_step(s, self._column(evaluate_expr(s.expr, env), n))
        rb = self.rulebase
        x = np.stack([env[v.name] for v in rb.inputs], axis=1)
        y = compiled(rb).evaluate_chunk(x) if n else np.empty((0, len(rb.outputs)))
        env.update({v.name: y[:, o] for o, v in enumerate(rb.outputs)})
        outputs = {o.name: self._run_output(o, self._column(evaluate_expr(o.expr, env), n))
                   for o in self.model.outputs}
        env.update(outputs)
        self.signals = {k: v for k, v in env.items() if k not in self.params}
        return outputs

    def _run_step(self, s, arg: np.ndarray) -> np.ndarray:
        if s.op == Op.ASSIGN:
            return arg
        mem = self._memory[s.name]
        fresh = np.isnan(mem)
        if s.op == Op.DELTA:
            value = np.where(fresh, np.where(np.isnan(arg), np.nan, 0.0), arg - mem)
            keep = arg
        elif s.op == Op.PREV:
            value = np.where(fresh, arg, mem)
            keep = arg
        else:   # LOWPASS
            a, b = s.coeffs
            value = np.where(fresh, arg, a * mem + b * arg)
            keep = value
        self._memory[s.name] = np.where(np.isfinite(keep), keep, mem)
        return value

    def _run_output(self, out, value: np.ndarray) -> np.ndarray:
        state = self._state[out.name]
        finite = np.isfinite(value)
        if out.kind == OutputKind.DIRECT:
            state = np.where(finite, np.clip(value, out.lo, out.hi), state)
            self._state[out.name] = state
            return state.copy()
        increment = np.where(finite, value, 0.0)
        if out.kind == OutputKind.INCREMENT:
            state = np.clip(state + increment, out.lo, out.hi)
            self._state[out.name] = state
            return state.copy()
        with np.errstate(divide="ignore"):
            v_lo, v_hi = 1.0 / out.hi, 1.0 / out.lo
        state = np.clip(state + increment, v_lo, v_hi)
        self._state[out.name] = state
        return 1.0 / state

    def set_consequent_values(self, output: str, values: np.ndarray) -> None:
        """Set the singleton values of a rule-base output's terms (the learned parameters)."""
        var = self.rulebase.outputs[self.rulebase.output_index(output)]
        values = np.asarray(values, dtype=float)
        if values.shape != (var.n_terms,):
            raise ValueError(f"{output} has {var.n_terms} terms, got {values.shape} values")
        if np.any(var.kinds != TermKind.SINGLETON):
            raise ValueError(f"{output}: only singleton terms have a single value to set")
        if not np.all(np.isfinite(values)):
            raise ValueError(f"{output}: values must be finite")
        var.params[:, 0] = values
