"""Shared pytest fixture for the FMU checks: the unpacked FMUs, once per module."""

from __future__ import annotations

import pytest

from stickslip_checks.artifacts import Fmus, fmu_paths


@pytest.fixture(scope="module")
def built():
    """The unpacked FMUs, or the error that says how to build them (see `need`)."""
    try:
        paths = fmu_paths()
    except FileNotFoundError as error:
        yield error
        return
    fmus = Fmus(paths)
    yield fmus
    fmus.close()


def need(value):
    """Fails (never skips) the calling test when `value` is the build error."""
    if isinstance(value, Exception):
        pytest.fail(str(value), pytrace=False)
    return value
