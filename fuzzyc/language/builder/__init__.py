"""Syntax objects -> Model, by concern: names and scopes (core), the signal chain (chain),
linguistic variables and terms (terms), rules, tables and blocks (rules), verify properties
(properties). The importers of other formats share the rule assembly (RuleSpec,
assemble_rulebase, merge_rules) and the shape table (PLAIN_SHAPES)."""
from .core import Builder
from .rules import RuleSpec, assemble_rulebase, merge_rules
from .terms import PLAIN_SHAPES

__all__ = ["Builder", "PLAIN_SHAPES", "RuleSpec", "assemble_rulebase", "merge_rules"]
