"""Gymnasium environments as plants (plants/gym_env.py): the shipped CartPole example, a
replay of a loop in Gymnasium itself, a hand-computed toy environment, and the errors."""
import json
import sys
from pathlib import Path

import numpy as np
import pytest

from fuzzyc.cli import main
from fuzzyc.errors import FuzzycError
from fuzzyc.plants import scenario as scenarios
from fuzzyc.runtime.simulate import simulate, summarize

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "gymnasium"
NEED_GYM = "Gymnasium is an optional extra: pip install 'fuzzyc[gym]'"


@pytest.fixture
def gym():
    return pytest.importorskip("gymnasium", reason=NEED_GYM)


def cartpole(overrides=None):
    return scenarios.load(EXAMPLE / "cartpole.yaml",
                          {"controller.rulebase": str(EXAMPLE / "cartpole.fz"),
                           **(overrides or {})})


def test_the_example_command_balances_cartpole_for_all_500_steps(gym, tmp_path, capsys):
    # the command of examples/gymnasium/cartpole.yaml, 20 loops (20 environment seeds):
    # CartPole-v1 truncates at 500 steps; every loop gets there without falling
    code = main(["simulate", str(EXAMPLE / "cartpole.fz"), "--scenario",
                 str(EXAMPLE / "cartpole.yaml"), "--batch", "20", "-o", str(tmp_path)])
    assert code == 0
    metrics = json.loads((tmp_path / "summary.json").read_text())["metrics"]
    assert metrics["fell (1) or survived (0)"]["max"] == 0
    assert metrics["episode return (500: every step survived)"]["min"] == 500
    assert metrics["mean pole angle"]["max"] < 0.01                  # rad, of 0.21 allowed
    assert (tmp_path / "trace.png").exists() and (tmp_path / "trace.csv").exists()


def test_the_pendulum_example_swings_up_and_holds_the_rod(gym):
    # Pendulum-v1 starts anywhere with at most 2 N m: 20 seeds are all upright within 0.1 rad
    # (cos > cos 0.1 = 0.995) by 5 s and stay there to the end (measured: by 3.95 s at the
    # latest over 100 seeds)
    sc = scenarios.load(EXAMPLE / "pendulum.yaml",
                        {"controller.rulebase": str(EXAMPLE / "pendulum.fz")})
    summary = summarize(sc, simulate(sc, batch=20))
    assert summary["upright (within 0.1 rad) from"]["max"] < 5.0
    assert summary["lowest cos(theta) after 5 s"]["min"] > 0.995


def test_the_c_back_end_takes_the_same_actions(gym):
    # the compiled controller (float32) against the same three environments: its force is
    # the engine's within float32 rounding, never on the other side of 0, so every action
    # and the whole trajectory are the same
    pytest.importorskip("fuzzyc.backends.c.load")
    import shutil
    if shutil.which("gcc") is None:
        pytest.skip("no C compiler")
    sc = cartpole({"duration": "4"})
    numpy_run, c_run = simulate(sc, batch=3), simulate(sc, batch=3, backend="c")
    np.testing.assert_allclose(c_run["force"], numpy_run["force"], rtol=0, atol=1e-6)
    assert (np.sign(c_run["force"]) == np.sign(numpy_run["force"])).all()
    np.testing.assert_array_equal(c_run["theta"], numpy_run["theta"])


def test_the_wrong_sign_falls_and_the_fall_is_held(gym):
    # max_lean = -0.2 rad pushes away from under the pole: every loop falls within a second;
    # after the fall the loop holds (return constant, reward 0, terminated stays 1)
    sc = cartpole({"controller.params.max_lean": "-0.2"})
    trace = simulate(sc, batch=5)
    assert (trace["terminated"][-1] == 1).all()
    fell = np.argmax(trace["terminated"] > 0, axis=0)                 # the period it fell
    assert (fell < 50).all()
    for loop, k in enumerate(fell):
        assert trace["return"][-1, loop] == k + 1                   # 1 per step lived
        assert (trace["reward"][k + 1:, loop] == 0).all()
        assert (trace["theta"][k:, loop] == trace["theta"][k, loop]).all()
        assert abs(trace["theta"][k, loop]) > 0.2094 or abs(trace["x"][k, loop]) > 2.4


def test_a_loop_replays_in_gymnasium_from_its_seed(gym):
    # reset CartPole-v1 with the trace's env_seed, step it with the actions the mapping gives
    # for the recorded force (u(-1), the lower end of force's range, -1, is action 0):
    # the observations are the trace's, to the last bit
    trace = simulate(cartpole({"duration": "2"}), batch=3, seed=7)
    loop = 2
    env = gym.make("CartPole-v1")
    observation, _ = env.reset(seed=int(trace["env_seed"][0, loop]))
    force = np.concatenate([[-1.0], trace["force"][:-1, loop]])
    for k, u in enumerate(force):
        observation, *_ = env.step(int(abs(u - 1) < abs(u + 1)))
        recorded = [trace[name][k, loop] for name in ("x", "x_dot", "theta", "theta_dot")]
        assert list(observation.astype(float)) == recorded
    assert len(np.unique(trace["env_seed"][0])) == 3                  # a seed per loop


def toy_scenario(tmp_path, plant: str, controller_output: str = "inflow") -> Path:
    rules = tmp_path / "fill.fz"
    rules.write_text(f"""controller fill {{
  period 100 ms
  input level in [0, 20]
  let e in [0, 20] = level
  terms e : uniform L H
  var v in [0, 1] default 0
  terms v : singletons Z=0 O=1
  rule r1: if e is L then v is O
  rule r2: if e is H then v is O
  output {controller_output} in [-10, 10] = 5 * v
}}
""")
    path = tmp_path / "toy.yaml"
    path.write_text(f"""plant:
{plant}
controller:
  rulebase: {rules}
  initial: {{{controller_output}: 5}}
duration: 1.0
period: 0.1
""")
    return path


TANK = """  model: gymnasium
  env: gym_toy_env:Tank
  kwargs: {rate: 2.0, limit: 1.0}
  observations: {1: level10, 0: level}
  action: inflow"""
TOY = ["gym_toy_env"]     # the user's module: imported only when allowed (docs/security.md)


def test_a_class_by_name_with_kwargs_and_a_continuous_action(gym, tmp_path):
    # the controller asks for inflow 5; the Box is [-1, 1], so 1 reaches the tank: the level
    # rises 2 * 1 * 0.1 = 0.2 a step from its start l0 in [0, 0.01); it reaches the limit 1.0
    # in the 5th step (0.8 + l0 < 1 <= 1.0 + l0): terminated, then held
    sc = scenarios.load(toy_scenario(tmp_path, TANK), allow_import=TOY)
    trace = simulate(sc, batch=4)
    start = trace["level"][0] - 0.2
    assert ((0 <= start) & (start < 0.01)).all()
    np.testing.assert_allclose(trace["level"][:5], start + 0.2 * np.arange(1, 6)[:, None],
                               atol=1e-12)
    np.testing.assert_allclose(trace["level10"], 10 * trace["level"], atol=1e-12)
    assert (trace["terminated"][:4] == 0).all() and (trace["terminated"][4:] == 1).all()
    assert (trace["level"][5:] == trace["level"][4]).all()            # held after the end
    assert (trace["return"][-1] == 5).all() and (trace["truncated"] == 0).all()


def error(path, *calls, allow=TOY):
    with pytest.raises(FuzzycError) as info:
        sc = scenarios.load(path, allow_import=allow)
        for call in calls:
            call(sc)
    return info.value.diagnostics[0].format()


def test_mistakes_in_a_gym_plant_are_located(gym, tmp_path):
    run = [lambda sc: simulate(sc)]
    allowed = ["no_such_module", "collections", "os"]    # past the allow: the class checks
    cases = [
        (TANK.replace("gym_toy_env:Tank", "CartPol-v1"), "toy.yaml:3", "CartPol"),
        (TANK.replace("gym_toy_env:Tank", "no_such_module:Tank"), "toy.yaml:3",
         "no module `no_such_module`"),
        (TANK.replace("gym_toy_env:Tank", "collections:OrderedDict"), "toy.yaml:3",
         "not a gymnasium.Env subclass"),
        (TANK.replace("gym_toy_env:Tank", "os:system"), "toy.yaml:3",
         "not a gymnasium.Env subclass"),
        (TANK.replace("rate: 2.0", "rat: 2.0"), "toy.yaml:4", "rat"),
        (TANK.replace("1: level10", "7: level10"), "toy.yaml:5", "not index 7"),
        (TANK.replace("0: level}", "0: reward}"), "toy.yaml:5", "writes itself"),
        (TANK + "\n  discrete: {0: -1}", "toy.yaml:7", "continuous actions"),
        # an integer of 400 digits is no float (OverflowError in math.isfinite, the fuzzer)
        (TANK + "\n  discrete: {0: 1" + "0" * 400 + "}", "toy.yaml:7", "action number"),
        (TANK + "\n  randomize: {rate: 0.1}", "toy.yaml:7", "unknown key"),
        (TANK.replace("action: inflow", "action: [inflow, 3]"), "toy.yaml:6", "output name"),
        # units: of an observation or an action, as short printable text
        (TANK + "\n  units: {levle: m}", "toy.yaml:7", "observation or action: unit text"),
        (TANK + "\n  units: {level: 3}", "toy.yaml:7", "observation or action: unit text"),
        (TANK + "\n  units: {level: \"m\\nx\"}", "toy.yaml:7", "unit text"),
    ]
    for plant, where, what in cases:
        message = error(toy_scenario(tmp_path, plant), *run, allow=TOY + allowed)
        assert where in message and what in message, (plant, message)
    # not allowed: refused at the key, naming the option (tests/test_security_scenarios.py)
    message = error(toy_scenario(tmp_path, TANK), *run, allow=())
    assert "toy.yaml:3" in message and "--allow-import" in message


def test_units_of_the_plants_signals_for_the_plots(gym, tmp_path):
    # the scenario's units, and the episode's scores dimensionless (`-`); env_seed has none
    from fuzzyc.runtime.simulate import signal_units
    sc = scenarios.load(toy_scenario(tmp_path, TANK + "\n  units: {level: m, inflow: m/s}"),
                        allow_import=TOY)
    units = signal_units(sc)
    assert {k: units.get(k) for k in ("level", "inflow", "level10", "return", "reward",
                                      "terminated", "truncated", "env_seed")} == {
        "level": "m", "inflow": "m/s", "level10": None, "return": "-", "reward": "-",
        "terminated": "-", "truncated": "-", "env_seed": None}


def test_a_nan_action_stops_the_run_with_a_message(gym, tmp_path):
    from fuzzyc.plants import gym_env
    sc = scenarios.load(toy_scenario(tmp_path, TANK), allow_import=TOY)
    plant = sc.plant_module()
    state = plant.initial_state(plant.params, 2)
    with pytest.raises(FuzzycError, match=r"`inflow` is nan in loop 1 at t = 0.3 s"):
        plant.step(plant.params, state, {"inflow": np.array([0.0, np.nan])}, 0.3, 0.1)
    assert gym_env.EPISODE == ("reward", "return", "terminated", "truncated", "env_seed")


def test_without_gymnasium_the_message_says_how_to_install(tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "gymnasium", None)     # import gymnasium -> ImportError
    message = error(toy_scenario(tmp_path, TANK), lambda sc: simulate(sc))
    assert "pip install 'fuzzyc[gym]'" in message


def test_discrete_actions_go_to_the_nearest_mapped_value(gym, tmp_path):
    # MountainCar-v0 has actions 0, 1, 2 (push left, none, right)
    def actions(extra, outputs):
        path = tmp_path / "car.yaml"
        path.write_text("plant:\n  model: gymnasium\n  env: MountainCar-v0\n"
                        f"  observations: [position, velocity]\n  action: push\n{extra}")
        plant = scenarios.load(path).plant_module()
        state = plant.initial_state(plant.params, len(outputs))
        return list(plant._action(plant.params, state["env"], {"push": np.array(outputs)},
                                  0.0, len(outputs)))
    # {0: -1, 1: 0, 2: 1}: -0.6 -> 0; -0.4 and 0.4 -> 1; 0.6 -> 2; 0.5 is as near 0 as 1:
    # the tie goes to the first listed, action 1
    assert actions("  discrete: {0: -1, 1: 0, 2: 1}\n",
                   [-0.6, -0.4, 0.4, 0.6, 0.5]) == [0, 1, 1, 2, 1]
    # without `discrete` the output is the action number, rounded to the nearest of 0, 1, 2
    assert actions("", [0.4, 0.6, 1.7, 5.0, -3.0]) == [0, 1, 2, 2, 0]


def test_wall_clock_pacing_runs_the_same_loop(gym):
    # --pace wall sleeps to the clock between steps: the same 10 steps, the same values
    sc = cartpole({"duration": "0.2"})
    sim, wall = simulate(sc, batch=2), simulate(sc, batch=2, pace="wall")
    assert wall.steps == sim.steps == 10
    for name in ("x", "theta", "force", "return", "env_seed"):
        np.testing.assert_array_equal(wall[name], sim[name])
