"""fuzzyc.runtime: controllers in fixed-period loops against plants, batched.

The API (stable; plants, the CLI, the verifier and the learner build on it):

Plants (modules of fuzzyc.plants) are pure and batched:
    INPUTS, OUTPUTS: tuple[str, ...]                         names on the signal bus
    XxxParams: a dataclass; fields scalars or (N,) arrays (randomized plants in a batch)
    initial_state(params, batch, rng) -> dict[str, (N,)]
    step(params, state, inputs: dict[str, (N,)], t, dt, rng) -> (new_state, outputs)
    (an input absent from `inputs` falls back to the params, e.g. a fixed workpiece height)

Blocks (runtime.blocks) have input_names, output_names, reset(batch), step(signals) -> dict:
    PlantBlock(plant_module, params, inputs, outputs, seed=0)
    ControllerBlock(controller, param_inputs=[], rename={}, expose=[])
        wraps fuzzyc.engine.chain.Controller or the C-backed CController (anything with
        input_names/output_names/reset/step); param_inputs: controller params that follow a
        bus signal (set-point schedules); expose: internal signals (controller.signals) to
        put on the bus, e.g. e1, e2
    FunctionBlock(fn, input_names, output_names)               fn(**inputs) -> dict
    ScheduleBlock(output, [(t0, v0), (t1, v1), ...])           piecewise-constant signal
    SensorFault(signal, start, length, stuck) (runtime.faults)  a measurement reads NaN or
        sticks over a per-loop window; the true value stays on the bus as `signal@plant`
  The bus also carries floats `t` (start of the period, s) and `dt` (the period, s).
  A block with `initial_outputs() -> dict` seeds the bus before the first period.

The loop (runtime.loop):
    run(blocks, period, duration, batch=1, pace="sim"|"wall", progress=False,
        initial=None, record=None, decimate=1) -> Trace
  blocks run in list order every period; pace="wall" sleeps to the wall clock and counts
  deadline misses (Trace.deadline_misses).

Traces (runtime.trace): Trace.time (T,), Trace.signals {name: (T, N)}, trace["name"],
    .select(i), .to_csv(path, loops=None) (atomic), Trace.from_csv(path).
Plots (runtime.plots): plot_trace(trace, path, signals=None, references=None, title="").
Metrics (runtime.metrics): settling_time, overshoot, steady_state_error, chattering,
    steady_change, event_count, moving_average — over (T, N) arrays, one value per loop.
Scenarios (runtime.simulate, with fuzzyc.plants.scenario.load(name_or_path, overrides)):
    simulate(scenario, batch=1, baseline=False, backend="numpy", seed=0, randomize=False,
             progress=False, record=None, pace="sim", first=0) -> Trace
    summarize(scenario, trace) -> {label: {mean, min, max, unit}}
    loop_metrics(scenario, trace) -> {label: (N,) values}; summarize_values(scenario, those)
    build(scenario, controller, batch=1, seed=0, randomize=False, expose=(), first=0) -> blocks
      loop k of the batch is loop first + k of a campaign: its plant params and noise come
      from streams keyed by (seed, first + k) (runtime.noise.KeyedNoise)
Campaigns (runtime.campaign, docs/campaigns.md): Cluster(workers=None, scheduler=None,
    chunk=10000, progress=None); simulate_campaign(scenario, batch, cluster, **options) ->
    Campaign(batch, metrics, summary, trace of the first loops); map_chunks(task, items,
    cluster) -> [task(item)...] in this process or on Dask
    load_controller(scenario, batch, backend="numpy") -> controller with the scenario's params
    references(scenario) -> {signal: set point} for plots
  Block order: schedules -> plant (sees the controller outputs of the previous period, u(-1)
  the first time) -> observers -> controller. A 40-ms sample period therefore has one period
  of delay from measurement to actuation, as on the machine.
"""
from .blocks import ControllerBlock, FunctionBlock, PlantBlock, ScheduleBlock
from .faults import SensorFault
from .loop import run
from .trace import Trace

__all__ = ["ControllerBlock", "FunctionBlock", "PlantBlock", "ScheduleBlock", "SensorFault",
           "Trace", "run"]
