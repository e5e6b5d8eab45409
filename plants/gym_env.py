"""Any environment with the Gymnasium API as the plant of a loop (`plant: {model: gymnasium}`).

    plant:
      model: gymnasium
      env: CartPole-v1            # a registered id (gymnasium.make), or module:Class, a
                                  # gymnasium.Env subclass of a module the user allowed
                                  # (--allow-import MODULE; never the file alone)
      kwargs: {}                  # keyword arguments of gymnasium.make or of the class
      observations: [x, x_dot, theta, theta_dot]   # observation index -> bus name
                                  # (a list, null skips an index; or a mapping {2: theta})
      action: push                # the controller output(s) that make the action
      discrete: {0: -1, 1: 1}     # Discrete actions: action n where the output is nearest to
                                  # its value (default: the output is the action number)
      units: {theta: rad}         # the observations' and actions' units, for plot axes (an
                                  # environment declares none); `-` for a dimensionless one

A batch of N loops is one `gymnasium.vector.SyncVectorEnv` of N copies; each period is one
`step` of every copy with the controller outputs of the previous period (the plant contract of
fuzzyc.runtime). Loop i's environment is reset with its own seed, drawn from the run's seed
and put on the bus as `env_seed` (reset an environment with it to replay the loop).

Besides the observations the plant writes `reward`, `return` (the reward summed over the
episode), `terminated` and `truncated` (0/1, on from the period the episode ended): all four
dimensionless (a reward is a score), `-` on a plot's axis. The loop
runs one episode: once it has ended, that loop's signals hold their last values and its
reward is 0 (the vector environment resets the copy underneath; nothing of the next episode
reaches the bus).
"""
from __future__ import annotations

import importlib
import importlib.util
import re
from dataclasses import dataclass, field
from typing import Any, Callable

import numpy as np

from .registry import ALLOW_HINT, allowed_module
from .scenario_schema import finite_number, shown

MODEL = "gymnasium"
KEYS = {"model", "env", "kwargs", "observations", "action", "discrete", "units"}
EPISODE = ("reward", "return", "terminated", "truncated", "env_seed")
SCORES = ("reward", "return", "terminated", "truncated")     # dimensionless episode signals
CLASS_REF = re.compile(r"([A-Za-z_][A-Za-z0-9_.]*):([A-Za-z_][A-Za-z0-9_]*)")
NAME = re.compile(r"[A-Za-z_][A-Za-z0-9_]*")
SEEDS = 10 ** 9
INSTALL = "Gymnasium is not installed: pip install 'fuzzyc[gym]' (or pip install gymnasium)"


@dataclass
class GymParams:
    env: str
    kwargs: dict = field(default_factory=dict)
    observations: dict[int, str] = field(default_factory=dict)   # index -> bus name
    action: list[str] = field(default_factory=list)
    discrete: dict[int, float] | None = None                     # action number -> value
    # a gymnasium.Env subclass passed from Python (fuzzyc.verify's scenarios=): `env` is then
    # its name, for messages; a file can only name one (a string), never pass one
    env_class: type | None = None
    units: dict[str, str] = field(default_factory=dict)         # signal -> unit, for plots


def gymnasium():
    """The gymnasium package, or the error that says how to install it."""
    from fuzzyc.errors import Diagnostic, FuzzycError
    try:
        import gymnasium as gym
    except ImportError:
        raise FuzzycError([Diagnostic(None, INSTALL)]) from None
    return gym


class GymPlant:
    """A plant made of a Gymnasium environment; it has what a plant module has (INPUTS,
    OUTPUTS, initial_state, step), so the loop, the scenario checks and the verifier take it
    as they take ours. `error(dotted, message)` makes a FuzzycError at a scenario key."""

    def __init__(self, params: GymParams, error: Callable[[str, str], Exception],
                 allow_import: tuple[str, ...] = ()):
        self.params, self.error, self.allow_import = params, error, allow_import
        self.INPUTS = self.REQUIRED_INPUTS = tuple(params.action)
        self.OUTPUTS = (*params.observations.values(), *EPISODE)
        # what a plant module's UNITS holds (runtime.simulate.signal_units reads it)
        self.UNITS = {**{name: "-" for name in SCORES}, **params.units}

    # --- the plant contract ------------------------------------------------------------------
    def initial_state(self, params: GymParams, batch: int, rng=None) -> dict[str, Any]:
        env = self._vector_env(params, batch)
        self._check_spaces(params, env)
        rng = rng if rng is not None else np.random.default_rng(0)
        # drawn through uniform (which the verifier's KeyedNoise also offers): a loop keeps its
        # seed when the verifier re-runs it in another batch; below 10^9, so the 9 digits of a
        # trace's CSV keep it exact
        seeds = np.floor(rng.uniform(0.0, SEEDS, batch)).astype(np.int64)
        observation, _ = env.reset(seed=[int(s) for s in seeds])
        zeros = np.zeros(batch)
        return {"env": env, "observation": _observed(params, observation, batch),
                "reward": zeros, "return": zeros, "terminated": zeros, "truncated": zeros,
                "env_seed": seeds.astype(float)}

    def step(self, params: GymParams, state: dict, inputs: dict[str, np.ndarray], t: float,
             dt: float, rng=None) -> tuple[dict, dict[str, np.ndarray]]:
        env = state["env"]
        batch = len(state["env_seed"])
        ended = (state["terminated"] + state["truncated"]) > 0
        observation, reward, terminated, truncated, _ = env.step(
            self._action(params, env, inputs, t, batch))
        observation = _observed(params, observation, batch)
        live = ~ended
        reward = np.where(live, np.asarray(reward, float), 0.0)
        new = {"env": env,
               "observation": {k: np.where(live, v, state["observation"][k])
                               for k, v in observation.items()},
               "reward": reward, "return": state["return"] + reward,
               "terminated": np.where(live & np.asarray(terminated), 1.0, state["terminated"]),
               "truncated": np.where(live & np.asarray(truncated), 1.0, state["truncated"]),
               "env_seed": state["env_seed"]}
        outputs = {params.observations[i]: v for i, v in new["observation"].items()}
        outputs.update({k: new[k] for k in EPISODE})
        return new, outputs

    # --- the environment ---------------------------------------------------------------------
    def _vector_env(self, params: GymParams, batch: int):
        gym = gymnasium()
        factory = self._factory(gym, params)
        try:
            return gym.vector.SyncVectorEnv([factory] * batch)
        except TypeError as exc:          # a keyword the environment does not take
            raise self.error("plant.kwargs", f"{params.env}: {exc}") from None
        except gym.error.Error as exc:
            raise self.error("plant.env", str(exc)) from None

    def _factory(self, gym, params: GymParams) -> Callable[[], Any]:
        if params.env_class is not None:       # the user's own class object: nothing imported
            def make_own():
                return params.env_class(**params.kwargs)
            return make_own
        check_import(params.env, self.allow_import, self.error)   # again: nothing unasked
        ref = CLASS_REF.fullmatch(params.env)
        if ref is None:                    # a registered id
            def make():
                return gym.make(params.env, **params.kwargs)
            try:
                gym.spec(params.env)
            except gym.error.Error as exc:
                raise self.error("plant.env", f"{exc}") from None
            return make
        module_name, class_name = ref.groups()
        try:
            found = importlib.util.find_spec(module_name)
        except (ImportError, ValueError):
            found = None
        if found is None:
            raise self.error("plant.env", f"no module `{module_name}` can be imported; "
                                          f"install it, or put its folder on PYTHONPATH")
        cls = getattr(importlib.import_module(module_name), class_name, None)
        if not (isinstance(cls, type) and issubclass(cls, gym.Env)):
            raise self.error("plant.env", f"`{class_name}` of {module_name} is not a "
                                          f"gymnasium.Env subclass")

        def make():
            return cls(**params.kwargs)
        return make

    def _check_spaces(self, params: GymParams, env) -> None:
        gym = gymnasium()
        obs_space, act_space = env.single_observation_space, env.single_action_space
        size = gym.spaces.flatdim(obs_space) if isinstance(
            obs_space, (gym.spaces.Box, gym.spaces.Discrete)) else None
        if size is None:
            raise self.error("plant.observations", f"{params.env} observes a {obs_space}: "
                                                   "only Box and Discrete observations map")
        for index in params.observations:
            if index >= size:
                raise self.error("plant.observations", f"{params.env} observes {size} "
                                 f"values (index 0 to {size - 1}), not index {index}")
        if isinstance(act_space, gym.spaces.Discrete):
            if len(params.action) != 1:
                raise self.error("plant.action", f"{params.env} takes one of {act_space.n} "
                                 f"actions: name one controller output")
            numbers = set(params.discrete or {})
            wrong = sorted(n for n in numbers if not 0 <= n - act_space.start < act_space.n)
            if wrong:
                raise self.error("plant.discrete", f"{params.env} has actions "
                                 f"{act_space.start} to {act_space.start + act_space.n - 1}, "
                                 f"not {wrong[0]}")
        elif isinstance(act_space, gym.spaces.Box):
            if params.discrete is not None:
                raise self.error("plant.discrete", f"{params.env} takes continuous actions "
                                 f"({act_space}): leave out `discrete`")
            if len(params.action) != int(np.prod(act_space.shape)):
                raise self.error("plant.action", f"{params.env} takes {act_space}: name "
                                 f"{int(np.prod(act_space.shape))} controller output(s)")
        else:
            raise self.error("plant.action", f"{params.env} takes a {act_space}: only "
                                              "Discrete and Box actions map")

    def _action(self, params: GymParams, env, inputs: dict[str, np.ndarray], t: float,
                batch: int) -> np.ndarray:
        """The controller outputs as the vector environment's action array."""
        gym = gymnasium()
        values = [np.broadcast_to(np.asarray(inputs[name], float), (batch,))
                  for name in params.action]
        for name, value in zip(params.action, values):
            if not np.isfinite(value).all():
                loop = int(np.argmax(~np.isfinite(value)))
                raise self.error("plant.action", f"controller output `{name}` is "
                                 f"{value[loop]} in loop {loop} at t = {t:g} s: no action")
        space = env.single_action_space
        if isinstance(space, gym.spaces.Discrete):
            numbers, levels = self._levels(params, space)
            return numbers[np.argmin(np.abs(values[0][:, None] - levels[None, :]), axis=1)]
        action = np.stack(values, axis=1).reshape((batch,) + space.shape)
        return np.clip(action, space.low, space.high).astype(space.dtype)

    @staticmethod
    def _levels(params: GymParams, space) -> tuple[np.ndarray, np.ndarray]:
        """(action numbers, the output value that picks each), in the mapping's order (a tie
        goes to the first)."""
        mapping = params.discrete if params.discrete is not None else {
            n: float(n) for n in range(int(space.start), int(space.start + space.n))}
        return (np.array(list(mapping), dtype=space.dtype),
                np.array(list(mapping.values()), dtype=float))


def _observed(params: GymParams, observation, batch: int) -> dict[int, np.ndarray]:
    """index -> (N,) float values of the observations the scenario maps."""
    flat = np.asarray(observation, dtype=float).reshape(batch, -1)
    return {i: flat[:, i].copy() for i in params.observations}


def from_scenario(scenario) -> GymPlant:
    """The scenario's `plant:` section as a GymPlant; a value of the wrong shape is an error at
    its key."""
    spec = scenario.data["plant"]
    err = scenario.error

    def need(ok: bool, key: str, what: str):
        if not ok:
            raise err(f"plant.{key}", f"must be {what}, got {shown(spec.get(key))}")

    for key in spec:
        if key not in KEYS:
            from fuzzyc.errors import suggest
            raise err(f"plant.{key}", f"unknown key for a Gymnasium plant; "
                                      f"{suggest(str(key), sorted(KEYS))}")
    env_class = _own_class(spec.get("env"), err)
    env = env_class.__name__ if env_class else spec.get("env")
    need(isinstance(env, str) and env != "", "env",
         "an environment id (CartPole-v1) or module:Class")
    allow = tuple(getattr(scenario, "allow_import", ()))
    if env_class is None:
        check_import(env, allow, err)
    kwargs = spec.get("kwargs") or {}
    need(isinstance(kwargs, dict) and all(isinstance(k, str) for k in kwargs), "kwargs",
         "a mapping of keyword arguments")
    observations = _observations(spec.get("observations"), need)
    action = spec.get("action")
    action = [action] if isinstance(action, str) else action
    need(isinstance(action, list) and action != [] and all(
        isinstance(a, str) and NAME.fullmatch(a) for a in action), "action",
        "a controller output name or a list of them")
    discrete = spec.get("discrete")
    if discrete is not None:
        need(isinstance(discrete, dict) and discrete != {} and all(
            _integer(k) and finite_number(v) for k, v in discrete.items()), "discrete",
            "a mapping {action number: output value}")
        discrete = {int(k): float(v) for k, v in discrete.items()}
    units = spec.get("units") or {}
    signals = {*observations.values(), *action}
    need(isinstance(units, dict) and all(
        k in signals and isinstance(v, str) and 0 < len(v) <= 32 and v.isprintable()
        for k, v in units.items()), "units",
        "a mapping {observation or action: unit text} (`-` for a dimensionless one)")
    clash = sorted(set(observations.values()) & set(EPISODE))
    if clash:
        raise err("plant.observations", f"`{clash[0]}` is a signal the plant writes itself "
                                        f"({', '.join(EPISODE)}): name the observation otherwise")
    names = list(observations.values())
    twice = sorted({n for n in names if names.count(n) > 1})
    if twice:
        raise err("plant.observations", f"`{twice[0]}` names two observations")
    return GymPlant(GymParams(env, dict(kwargs), observations, list(action), discrete,
                              env_class, dict(units)), err, allow)


def _own_class(env, err) -> type | None:
    """`env` as a gymnasium.Env subclass the user passed from Python (a mapping given to
    fuzzyc.verify; YAML yields no class), or None for a name."""
    if not isinstance(env, type):
        return None
    if not issubclass(env, gymnasium().Env):
        raise err("plant.env", f"`{env.__name__}` is not a gymnasium.Env subclass")
    return env


def check_import(env: str, allow_import: tuple[str, ...], err) -> None:
    """Refuse, before anything is imported, an `env` that would import a module the user did
    not allow: `module:Class`, and gymnasium's own `module:Id-v0` (gymnasium.make imports the
    module). A plain id is looked up in Gymnasium's registry only."""
    if ":" not in env:
        return
    module = env.partition(":")[0]
    if not allowed_module(module, allow_import):
        allowed = ", ".join(allow_import) or "none"
        raise err("plant.env", f"{shown(env, '`')} would import the module "
                               f"{shown(module, '`')}, and a scenario file cannot make fuzzyc "
                               f"import code; name an environment id registered with Gymnasium "
                               f"(CartPole-v1, Pendulum-v1, ...), or {ALLOW_HINT} "
                               f"(allowed now: {allowed})", of_value=True)


def _integer(value) -> bool:
    return isinstance(value, int) and not isinstance(value, bool) and value >= 0


def _observations(value, need) -> dict[int, str]:
    """index -> name from a list (null skips an index) or a mapping."""
    what = "a list of names (index 0 first; null skips one) or a mapping {index: name}"
    if isinstance(value, list):
        value = {i: name for i, name in enumerate(value) if name is not None}
    need(isinstance(value, dict) and value != {} and all(
        _integer(i) and isinstance(n, str) and NAME.fullmatch(n) for i, n in value.items()),
        "observations", what)
    return dict(sorted(value.items()))
