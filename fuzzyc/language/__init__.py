"""The language front end: .fz text -> lark tree (grammar/) -> syntax objects (syntax) -> Model
(builder/), with the stated limits, units, numbers and rule conditions it checks on the way."""
