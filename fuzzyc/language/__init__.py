"""The language front end: .fz text -> lark tree -> syntax objects -> Model (grammar, parser, syntax, builder, limits, units, numbers, conditions)."""
