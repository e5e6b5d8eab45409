"""A Gymnasium environment whose every step is known by hand (for tests/test_gym_plant.py):
a tank filled at `rate` times the inflow action (a Box in [-1, 1]) every `dt`; it reports
[level, 10 * level] and terminates once the level reaches `limit`. Reward 1 per step."""
import gymnasium
import numpy as np


class Tank(gymnasium.Env):
    def __init__(self, rate: float = 2.0, dt: float = 0.1, limit: float = 1.0):
        self.rate, self.dt, self.limit = rate, dt, limit
        self.action_space = gymnasium.spaces.Box(-1.0, 1.0, (1,), np.float64)
        self.observation_space = gymnasium.spaces.Box(-np.inf, np.inf, (2,), np.float64)

    def reset(self, *, seed=None, options=None):
        super().reset(seed=seed)
        self.level = float(self.np_random.uniform(0.0, 0.01))
        return self._observe(), {}

    def step(self, action):
        self.level += self.rate * float(action[0]) * self.dt
        return self._observe(), 1.0, bool(self.level >= self.limit - 1e-12), False, {}

    def _observe(self):
        return np.array([self.level, 10.0 * self.level])
