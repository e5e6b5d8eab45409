"""fuzzyc.plants: plant models (pure batched functions) and the papers' scenarios in YAML.

Each plant module defines INPUTS, OUTPUTS, a *Params dataclass, initial_state(params, batch,
rng) and step(params, state, inputs, t, dt, rng) -> (state, outputs); see fuzzyc.runtime for
the contract and fuzzyc.plants.scenario for the scenario format.
"""
