"""Runs every property of a model with the methods that apply, strongest first."""
from __future__ import annotations

import os
import re
import shlex
import time
from collections.abc import Mapping
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from ..semantics.model import Model, Property, RuleBase
from ..engine.norms import combine
from . import coverage, outputs, proof, search, tables
from .result import Evidence, Result, Status

FINDING_PREFIX = "finding:"
DEFAULT_PREFIX = "default: "   # in a result's name: the file declared no properties
CROSSING = 0.5                 # where neighbouring terms of a Ruspini partition cross


@dataclass
class Options:
    backend: str = "numpy"          # closed loops drive the numpy engine or the generated C
    max_examples: int = 100         # hypothesis examples (and closed-loop cases)
    seed: int = 0
    grid_budget: int = 20000        # dense-grid points per property
    shrink_rounds: int = 4          # batched shrinking rounds for a failing closed loop
    report_dir: str | None = None   # counterexample plots go here
    only: str | None = None         # run only properties whose text contains this
    progress: Callable[[str], None] | None = None
    cluster: Any = None             # a runtime.campaign.Cluster: closed-loop cases in chunks
    prove: bool = False             # closed loops: reachable sets first (fuzzyc.verifier.reach)
    prove_boxes: int = 64           # branch-and-bound budget of boxes per closed loop
    noise_sigmas: float = 0.0       # Gaussian plant noise covered up to this many sigma
    allow_import: tuple = ()        # modules a scenario may import (--allow-import), no more
    scenarios: Any = None           # closed-loop name -> the user's scenario (API: own plants)


def covers_violation(note: str, evidence: list[Evidence]) -> bool:
    """A recorded finding explains a violation only if it names every rule-table place the
    tables report (the [...] part of each cell), so a new bad cell is never hidden by an old
    note. Violations found by proof or search are explained by the note as a whole."""
    for e in evidence:
        if e.method == "table" and e.status in (Status.VIOLATED, Status.WARNING):
            for cell in e.cells:
                places = re.findall(r"\[([^\]]+)\]", cell)
                if not places or not all(p in note for p in places):
                    return False
    return True


def finding_for(model: Model, prop: Property) -> str | None:
    """The note recording a known violation of this property: `note "finding: <text> ..."`."""
    for note in model.notes:
        if note.startswith(FINDING_PREFIX) and prop.text and \
                note[len(FINDING_PREFIX):].lstrip().startswith(prop.text):
            return note
    return None


def _finding(model: Model, prop: Property, evidence: list[Evidence]) -> str | None:
    note = finding_for(model, prop)
    return note if note and covers_violation(note, evidence) else None


def property_name(model: Model, prop: Property, parent: Property | None = None) -> str:
    base = os.path.basename(model.source_path or model.name)
    head = f"{parent.text.split('{')[0].strip()} :: " if parent else ""
    mark = DEFAULT_PREFIX if not model.properties else ""
    return f"{base}::{mark}{head}{prop.text or prop.kind}"


def default_level(rb: RuleBase) -> float:
    """The firing level a complete table over Ruspini partitions (neighbouring terms crossing
    at 0.5) reaches everywhere: the rule base's own AND of 0.5 over all its inputs (min 0.5,
    product 0.5^n). 0 for and = bounded difference, drastic, nilpotent min with n >= 2."""
    return float(combine([np.array(CROSSING)] * len(rb.inputs), rb.inference.and_, True))


def default_properties(model: Model) -> list[Property]:
    """What `fuzzyc verify` checks in a model that declares no properties (every imported
    model, a .fz without `verify`): the structural ones, which need no knowledge of the plant.
    consistent; complete (every cell of input terms, every output); covers every input at
    least default_level (left out when that is 0: no positive level can be asked of such an
    AND); bounded every rule-base output in its range. Not continuous (a design style, not a
    defect) nor monotone (needs the direction the designer intends).  With several rule
    blocks: consistent and complete over every block, covers per block."""
    texts = [("consistent", {}, "consistent"),
             ("complete", {"output": None}, "complete")]
    for rb in model.blocks:
        level = default_level(rb)
        if level > 0:
            names = [v.name for v in rb.inputs]
            texts.append(("covers", {"inputs": names, "level": level},
                          f"covers {', '.join(names)} at least {level:.12g}"))
    texts += [("bounded", {"signal": v.name, "lo": v.lo, "hi": v.hi},
               f"bounded {v.name} in [{v.lo:.12g}, {v.hi:.12g}]")
              for rb in model.blocks for v in rb.outputs]
    return [Property(kind, args, None, text) for kind, args, text in texts]


def reproduce_command(model: Model, prop: Property, options: Options,
                      extra: tuple[str, ...] = ()) -> str:
    args = ["fuzzyc", "verify", model.source_path or model.name, "--only", prop.text,
            "--seed", str(options.seed), "--max-examples", str(options.max_examples)]
    if options.backend != "numpy":
        args += ["--backend", options.backend]
    return " ".join(shlex.quote(a) for a in [*args, *extra])


def verify_model(model: Model, options: Options | None = None) -> list[Result]:
    options = options or Options()
    results = []
    for prop in model.properties or default_properties(model):
        if prop.kind == "closed_loop":
            checks = [c for c in prop.args["checks"] if _selected(options, c, prop)]
            if checks:
                results += _closed_loop(model, prop, checks, options)
            continue
        if not _selected(options, prop):
            continue
        if options.progress:
            options.progress(prop.text)
        start = time.perf_counter()
        evidence = check_property(model, prop, options)
        results.append(Result(prop, property_name(model, prop), evidence,
                              _finding(model, prop, evidence),
                              reproduce_command(model, prop, options),
                              time.perf_counter() - start))
    return results


def _selected(options: Options, prop: Property, parent: Property | None = None) -> bool:
    if not options.only:
        return True
    return options.only in prop.text or (parent is not None and options.only in parent.text)


def check_property(model: Model, prop: Property, options: Options) -> list[Evidence]:
    """The evidence on one rule-base or chain property.  A rule-base property is checked on
    the rule block it speaks of (fuzzyc.semantics.model, "Rule blocks"): the block of its
    output, the blocks that read all its inputs (covers), every block (consistent, complete
    or continuous without an output), each over its inputs' declared ranges, as a one-block
    model's rule base is."""
    a = prop.args
    if prop.kind == "bounded" and _block_with_output(model, a["signal"]) is None:
        return _bounded_chain(model, a["signal"], a["lo"], a["hi"], options)
    blocks = _blocks_of(model, prop)
    if isinstance(blocks, Evidence):
        return [blocks]
    if len(blocks) == 1:
        return _check_block(model, blocks[0], prop, options)
    return [_every_block([(rb.name, _check_block(model, rb, prop, options)) for rb in blocks])]


def _block_with_output(model: Model, name: str) -> RuleBase | None:
    return next((rb for rb in model.blocks if name in [v.name for v in rb.outputs]), None)


def _blocks_of(model: Model, prop: Property) -> list[RuleBase] | Evidence:
    """The rule blocks a rule-base property is about, or UNDECIDED evidence saying why none."""
    if len(model.blocks) == 1:
        return model.blocks
    a = prop.args
    output = a.get("output") if prop.kind != "bounded" else a["signal"]
    if output is not None:
        rb = _block_with_output(model, output)
        if prop.kind == "monotone" and a["input"] not in [v.name for v in rb.inputs]:
            return Evidence("proof", Status.UNDECIDED, f"`{output}` (block `{rb.name}`) does "
                            f"not read `{a['input']}` itself: monotonicity through several "
                            "rule blocks is not checked")
        return [rb]
    if prop.kind == "covers":
        blocks = [rb for rb in model.blocks
                  if set(a["inputs"]) <= {v.name for v in rb.inputs}]
        return blocks or Evidence("proof", Status.UNDECIDED, "no one rule block reads all of "
                                  + ", ".join(a["inputs"]) + ": covers is about one block")
    return model.blocks


def _every_block(parts: list[tuple[str, list[Evidence]]]) -> Evidence:
    """One piece of evidence for a property that must hold in every block: a block's
    violation as it is (named), else the weakest block's verdict (PROVED only if each block's
    is), its detail naming each block's."""
    order = [Status.PROVED, Status.HELD, Status.UNDECIDED]
    verdicts = []
    for name, evidence in parts:
        statuses = {e.status for e in evidence}
        bad = next((e for e in evidence if e.status == Status.VIOLATED), None)
        if bad is not None:
            return replace(bad, detail=f"block `{name}`: {bad.detail}")
        verdicts.append(next((s for s in order if s in statuses), Status.UNDECIDED))
    weakest = max(verdicts, key=order.index)
    detail = "; ".join(f"block `{name}`: {v.value}" + "".join(
        f" ({e.detail})" for e in evidence if e.status == v and e.detail)
        for (name, evidence), v in zip(parts, verdicts))
    method = "+".join(dict.fromkeys(e.method for _, ev in parts for e in ev
                                    if e.status in (Status.PROVED, Status.HELD)))
    return Evidence(method or "proof", weakest, detail,
                    cases=sum(e.cases for _, ev in parts for e in ev if e.status == weakest))


def _check_block(model: Model, rb: RuleBase, prop: Property, options: Options) -> list[Evidence]:
    a = prop.args
    n, s, budget = options.max_examples, options.seed, options.grid_budget
    flat_only = _unless_flat(rb)
    if flat_only and prop.kind in ("consistent", "complete", "continuous"):
        return [flat_only]
    if prop.kind == "consistent":
        return [tables.consistent(rb)]
    if prop.kind == "complete":
        return [tables.complete(rb, a["output"])]
    if prop.kind == "continuous":
        return [tables.continuous(rb, a["output"])]
    if prop.kind == "covers":
        proved = _unless_beyond(rb) or coverage.prove_covers(rb, a["inputs"], a["level"])
        if proved.status != Status.UNDECIDED:
            return [proved]
        return [proved, search.covers(rb, a["inputs"], a["level"], budget)]
    if prop.kind == "monotone":
        args = (a["output"], a["input"], a["direction"], a["where"])
        # the table only remarks or warns: the output is a defuzzified blend, not a cell
        evidence = [flat_only or _table_remark(tables.monotone(rb, *args)),
                    _unless_beyond(rb) or proof.prove_monotone(rb, *args)]
        if evidence[-1].status == Status.UNDECIDED:
            evidence += search.monotone(rb, *args, budget, n, s)
        return evidence
    if prop.kind == "bounded":
        return _bounded(rb, a["signal"], a["lo"], a["hi"], options)
    return [Evidence("none", Status.UNDECIDED, f"unknown property kind `{prop.kind}`")]


def _table_remark(table: Evidence) -> Evidence:
    """A monotone property is about the defuzzified output, which the rule table does not fix:
    a monotone table is no proof (max-min center of area dips inside cells) and a table that
    goes against the direction (a reversal, or a cell holding two conclusions from OR rules)
    is no violation until an evaluation shows the output moving back. Either is a remark."""
    if table.status == Status.PROVED:
        return Evidence("table", Status.UNDECIDED, f"remark: the rule table is monotone "
                        f"({table.detail}); that decides nothing about the defuzzified output")
    if table.status == Status.VIOLATED:
        return Evidence("table", Status.WARNING, f"{table.detail} on the rule table; a warning "
                        f"about the table: the verdict rests on evaluations of the output",
                        cells=table.cells)
    return table


def _unless_flat(rb) -> Evidence | None:
    """UNDECIDED evidence when a rule has a nested condition: the rule-table analyses read
    one term per input and rule."""
    if not rb.conditions:
        return None
    return Evidence("table", Status.UNDECIDED, f"{rb.nested_rules()} has a nested condition, "
                                               "which the rule-table analysis does not read")


def _unless_beyond(rb) -> Evidence | None:
    """UNDECIDED evidence when the rule base is outside every proof method's scope."""
    reason = proof.beyond_proofs(rb)
    if reason is None:
        return None
    return Evidence("proof", Status.UNDECIDED, reason + "; the search decides")


def _bounded(rb: RuleBase, signal: str, lo: float, hi: float, options: Options):
    """bounded on an output of the rule base rb."""
    proved = _unless_beyond(rb) or proof.prove_bounded(rb, signal, lo, hi)
    if proved.status == Status.UNDECIDED:     # linear consequents: their corner hull
        proved = proof.prove_bounded_linear(rb, signal, lo, hi) or proved
    if proved.status != Status.UNDECIDED:
        return [proved]
    return [proved] + search.bounded(rb, signal, lo, hi, options.grid_budget,
                                     options.max_examples, options.seed)


def _bounded_chain(model: Model, signal: str, lo: float, hi: float, options: Options):
    """bounded on a signal of the chain: an output, or a let."""
    out = next((o for o in model.outputs if o.name == signal), None)
    if out is not None:
        return [outputs.output_bounded(model, out, lo, hi, options.grid_budget)]
    return [outputs.let_bounded(model, signal, lo, hi)]


def _closed_loop(model: Model, prop: Property, checks: list[Property],
                 options: Options) -> list[Result]:
    from . import closed_loop
    start = time.perf_counter()
    if options.progress:
        options.progress(prop.text)
    verdicts = closed_loop.check(model, prop, checks, options)
    elapsed = time.perf_counter() - start
    given = (options.scenarios or {}).get(prop.args["scenario"])
    return [Result(c, property_name(model, c, prop), ev, _finding(model, c, ev),
                   _reproduce(model, prop, c, options, given), elapsed / len(checks))
            for c, ev in zip(checks, verdicts)]


def _reproduce(model: Model, loop: Property, check: Property, options: Options, given) -> str:
    """The command that checks `check` again; a loop on a scenario of the user's names it
    (`--scenario NAME=FILE`), or, given from Python as a mapping (an own plant object), is
    replayed by the same call: the command line has no plant object to pass."""
    if given is None:
        return reproduce_command(model, check, options)
    if not isinstance(given, Mapping):
        allowed = [a for m in options.allow_import for a in ("--allow-import", m)]
        return reproduce_command(model, check, options, (
            "--scenario", f"{loop.args['scenario']}={os.fspath(given)}", *allowed))
    backend = f", backend={options.backend!r}" if options.backend != "numpy" else ""
    return (f"fuzzyc.verify({model.source_path or model.name!r}, scenarios=<the same>, "
            f"only={check.text!r}, seed={options.seed}, "
            f"max_examples={options.max_examples}{backend})")
