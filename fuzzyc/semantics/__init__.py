"""What the language means, written once: the model (IR) and the registries of term shapes,
operators and signal-chain operations that every front end and back end reads."""
