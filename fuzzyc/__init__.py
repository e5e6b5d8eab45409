"""fuzzyc: a declarative language, compiler, verifier and runtime for fuzzy controllers."""
__version__ = "0.1.0"
