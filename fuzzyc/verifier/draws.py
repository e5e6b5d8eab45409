"""The same `--seed` draws the same cases in every process.

hypothesis (since 6.13x) mixes numeric literals of the *local* modules loaded in the process
into its draws ("local constants"). A pytest worker has loaded other modules than `fuzzyc
verify` has, so one seed drew other cases in the two, and a finding the CLI reproduces could
go unseen in the suite (or the reverse). While we draw, that pool is held empty: a private hook
of hypothesis, so where a version has no such hook there is nothing to hold and the draws are
as hypothesis makes them."""
from __future__ import annotations

import contextlib
from unittest import mock


@contextlib.contextmanager
def without_local_constants():
    try:
        from hypothesis.internal.conjecture import providers
        from hypothesis.internal.constants_ast import Constants
    except ImportError:
        yield
        return
    if not hasattr(providers, "_get_local_constants"):
        yield
        return
    with mock.patch.object(providers, "_get_local_constants", lambda: Constants()):
        yield
