"""What the language means, written once: the model (IR) and the registries of shapes and operators that every front end and back end reads."""
