"""The numpy engine, the reference semantics: memberships, norms, inference, defuzzification, the signal chain."""
