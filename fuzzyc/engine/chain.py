"""A Model's whole signal chain (steps, rule blocks, outputs) for a batch of independent loops.

Robustness to bad samples (a NaN or infinite raw input):
- stateful steps (delta, prev, lowpass) keep their last finite memory; their output for that
  sample is NaN when the argument is, so the rule base sees a NaN input;
- the rule base gives memberships 0 for NaN inputs, hence its defaults where nothing fires;
- an output whose expression is not finite for a sample holds its state: an INCREMENT or
  RECIPROCAL_INCREMENT treats a non-finite increment as 0, a DIRECT output keeps its last value
  (its `init` before the first finite one).  Outputs are therefore always finite.
A rule-base output with lock-previous (fuzzylite's) holds, per loop, its last value where no
rule fires (its default before any: a fresh controller has nothing to hold).
`set_consequent_values` changes the rule base of the model (the learned parameters belong to
the model, so exporting it after learning writes the learned values): it assigns the output a
new params array, as every change of a rule base the engine has compiled must (its arrays are
read-only, `fuzzyc.engine.inference.compiled`).

Speed: the model is read at `reset()` (expressions compiled to closures, the engine's tables
fetched, saturation limits taken), so a step does only the batch's arithmetic.  A model
changed in place other than through `set_consequent_values` (a term moved, a limit changed)
takes effect at the next `reset()`; `params` are read every step (schedules change them).
Once every memory holds a finite value and a step's values are all finite (the usual case), the
steps and outputs skip their masks: the same arithmetic on the values the masks would keep.
"""
from __future__ import annotations

import functools
import math

import numpy as np
import sympy

from .inference import compiled
from .expressions import clip, compile_value
from ..semantics.chain_ops import OUTPUT_OPS, STEP_OPS, run_chain
from ..semantics.model import Model, TermKind, set_entries
from ..language.numbers import real_array
from .held_outputs import Held


class Controller:
    def __init__(self, model: Model, batch: int = 1, semantics: str = "exact"):
        """`semantics`: the rule base's arithmetic, exact or a tool's (formats.tool_semantics:
        fuzzylite, pyfuzzylite, matlab, octave, optionally :RESOLUTION)."""
        self.model = model
        self.semantics = semantics
        self.input_names = [s.name for s in model.signals]
        self.output_names = [o.name for o in model.outputs]
        self.params = model.symbol_values()
        self.signals: dict[str, np.ndarray] = {}
        self.reset(batch)

    def reset(self, batch: int | None = None) -> None:
        """Forget all memories (steps and output states); optionally change the batch size.
        Reads the model again (see the module docstring)."""
        if batch is not None:
            self.batch = int(batch)
        n = self.batch
        # NaN memory = "no sample yet"; only finite values are ever stored.
        self._memory = {s.name: np.full(n, np.nan) for s in self.model.steps
                        if STEP_OPS[s.op].stateful}
        self._primed: set[str] = set()     # the steps whose memory is finite for every loop
        self._state = {o.name: np.full(n, OUTPUT_OPS[o.kind].initial_state(o))
                       for o in self.model.outputs}
        self.signals = {}
        # a bare name returns the caller's array itself: a memory keeps a copy of it
        self._steps = {s.name: (compile_value(s.expr), isinstance(s.expr, sympy.Symbol))
                       for s in self.model.steps}
        self._outputs = {o.name: (compile_value(o.expr), OUTPUT_OPS[o.kind].state_limits(o))
                         for o in self.model.outputs}
        # per rule block in order: its input names, its (index, output name)s, its engine, and
        # what gives its terms' activations to later blocks (fuzzylite's chains) or None
        self._blocks = [self._block(k) for k in range(len(self.model.blocks))]
        # per block the values its lock-previous outputs hold, per loop (fuzzyc.engine.held_outputs)
        self._held = [Held(sequence=False) for _ in self.model.blocks]

    def _block(self, k: int):
        """Block k as this controller runs it (see `_blocks`). Under fuzzylite's semantics a
        later block reads `V is t` of this block's output V as t's activation in V's fuzzy
        set, not as t's membership of V's value (formats.tool_semantics.reading_activations)."""
        rb, gives_activations = self.model.blocks[k], None
        if self.semantics == "exact":
            engine = compiled(rb)
        else:
            from ..formats import tool_semantics as tools
            if self.semantics in ("fuzzylite", "pyfuzzylite"):
                earlier = {v.name for b in self.model.blocks[:k] for v in b.outputs}
                rb = tools.reading_activations(rb, earlier)
                later = {v.name for b in self.model.blocks[k + 1:] for v in b.inputs}
                if later & {v.name for v in rb.outputs}:
                    gives_activations = functools.partial(tools.term_activations, rb)
            engine = tools.ToolEngine(rb, self.semantics, tools.file_settings(self.model))
        return ([v.name for v in rb.inputs], list(enumerate(v.name for v in rb.outputs)),
                engine, gives_activations)

    def _column(self, value, n: int) -> np.ndarray:
        """value as a float (N,) array: itself when it already is one (steps never write into
        their arguments, so sharing it is safe), else broadcast."""
        if isinstance(value, np.ndarray) and value.shape == (n,) and value.dtype == np.float64:
            return value
        return np.broadcast_to(np.asarray(value, dtype=float), (n,)).copy()

    def _input(self, name: str, value, n: int) -> np.ndarray:
        """A raw input as a float (N,) array: `_column`, for real numbers only (ValueError
        naming the input for None, a string, a bool, a datetime, a masked array...)."""
        if type(value) is np.ndarray and value.shape == (n,) and value.dtype == np.float64:
            return value        # the usual case: no check needed
        return self._column(real_array(name, value), n)

    def step(self, inputs: dict[str, np.ndarray]) -> dict[str, np.ndarray]:
        """One sample for every loop: raw inputs (N,) each -> controller outputs (N,) each."""
        n = self.batch
        env: dict = dict(self.params)
        try:
            for name in self.input_names:
                env[name] = self._input(name, inputs[name], n)
        except KeyError:
            missing = [name for name in self.input_names if name not in inputs]
            raise KeyError(f"no value for input(s): {', '.join(missing)}") from None
        chain = FloatChain(self, env)
        with np.errstate(divide="ignore", invalid="ignore", over="ignore"):
            run_chain(self.model, chain)
        outputs = chain.outputs
        env.update(outputs)
        for name in self.params:    # env holds every param: what is left are the signals
            del env[name]
        self.signals = env
        return outputs

    def set_consequent_values(self, output: str, values: np.ndarray) -> None:
        """Set the singleton values of a rule-base output's terms (the learned parameters)."""
        k, rb = next((k, rb) for k, rb in enumerate(self.model.blocks)
                     if output in [v.name for v in rb.outputs])
        var = rb.outputs[rb.output_index(output)]
        values = np.asarray(values, dtype=float)
        if values.shape != (var.n_terms,):
            raise ValueError(f"{output} has {var.n_terms} terms, got {values.shape} values")
        if np.any(var.kinds != TermKind.SINGLETON):
            raise ValueError(f"{output}: only singleton terms have a single value to set")
        if not np.all(np.isfinite(values)):
            raise ValueError(f"{output}: values must be finite")
        set_entries(var, "params", np.s_[:, 0], values)   # a new array: see the docstring
        self._blocks[k] = self._block(k)    # rebuilt for the new values


class FloatChain:
    """The chain walk's float domain (`fuzzyc.semantics.chain_ops`): one sample of a
    Controller's loops, numpy (N,) arrays.  Memories hold NaN until their first finite sample
    ("fresh"); a memory finite in every loop is primed, and its step skips the masks (the same
    values: see the module docstring)."""

    def __init__(self, controller: Controller, env: dict):
        self.c, self.env, self.n = controller, env, controller.batch
        self.outputs: dict[str, np.ndarray] = {}
        self.arg = None          # the current step's argument (maybe the caller's array)

    # -- arithmetic -----------------------------------------------------------------------

    @staticmethod
    def sub(a, b):
        return a - b

    @staticmethod
    def mix(a, x, b, y):
        return a * x + b * y

    @staticmethod
    def zero_unless_nan(x):
        return np.where(np.isnan(x), np.nan, 0.0)

    @staticmethod
    def clamp(x, lo, hi):
        return clip(x, lo, hi)

    @staticmethod
    def if_finite(test, then, otherwise):
        # a sum is finite only if every term is (the usual case: no mask)
        if math.isfinite(np.add.reduce(test)):
            return then
        return np.where(np.isfinite(test), then, otherwise)

    @staticmethod
    def finite_or_zero(x):
        return x if math.isfinite(np.add.reduce(x)) else np.where(np.isfinite(x), x, 0.0)

    @staticmethod
    def saturating_add(state, x, lo, hi):
        return clip(state + x, lo, hi)

    @staticmethod
    def reciprocal(o, state):
        return 1.0 / state

    # -- steps ----------------------------------------------------------------------------

    def argument(self, s, stateful: bool) -> np.ndarray:
        self.arg = self.c._column(self.c._steps[s.name][0](self.env), self.n)
        return self.arg

    def memory(self, s, rule, arg) -> np.ndarray:
        return self.c._memory[s.name]

    @staticmethod
    def may_be_seen(s) -> bool:
        return True     # arg - NaN is NaN where fresh: computed, then not selected

    def may_be_fresh(self, s) -> bool:
        return s.name not in self.c._primed

    def select(self, s, seen, fresh):
        if fresh is None:
            return seen
        return np.where(np.isnan(self.c._memory[s.name]), fresh, seen)

    def store(self, s, keep) -> None:
        memories, mem = self.c._memory, self.c._memory[s.name]
        if s.name in self.c._primed:
            if math.isfinite(np.add.reduce(keep)):
                alias = self.c._steps[s.name][1]
                memories[s.name] = keep.copy() if alias and keep is self.arg else keep
            else:
                memories[s.name] = np.where(np.isfinite(keep), keep, mem)
            return
        memories[s.name] = np.where(np.isfinite(keep), keep, mem)
        if not np.isnan(memories[s.name]).any():
            self.c._primed.add(s.name)

    def define(self, s, value) -> None:
        self.env[s.name] = value

    # -- rule blocks and outputs --------------------------------------------------------------

    def rule_blocks(self) -> None:
        env, n = self.env, self.n
        activations: dict[str, np.ndarray] = {}     # `V.t` of fuzzylite's chains
        for (inputs, outputs, engine, gives_activations), held in zip(self.c._blocks,
                                                                       self.c._held):
            # the block's inputs as rows (I, N), its outputs as rows (O, N)
            x = np.array([env[name] if name in env else activations[name]
                          for name in inputs])     # each one (N,) float
            y = engine.evaluate_rows(x, held) if n else np.empty((len(outputs), 0))
            env.update({name: y[o] for o, name in outputs})
            if gives_activations is not None:
                activations.update(gives_activations(x.T))

    def limits(self, o) -> tuple[float, float]:
        return self.c._outputs[o.name][1]

    def output_value(self, k: int, o) -> np.ndarray:
        return self.c._column(self.c._outputs[o.name][0](self.env), self.n)

    def output_state(self, o) -> np.ndarray:
        return self.c._state[o.name]

    def set_state(self, o, state) -> None:
        self.c._state[o.name] = state

    read_state = output_state

    def emit_output(self, k: int, o, result) -> None:
        # the state itself stays the controller's: the caller gets a copy
        self.outputs[o.name] = result.copy() if result is self.c._state[o.name] else result
