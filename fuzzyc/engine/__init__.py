"""The numpy engine, the reference semantics: memberships, norms, inference (`inference`),
defuzzification, the exact centroid, and the signal chain (`chain.Controller`)."""
