"""Shared pytest fixtures for the FMU checks: the unpacked FMUs, once per module, and the
packaged FMUs' paths by FMI version."""

from __future__ import annotations

import pytest

from stickslip_checks.artifacts import Fmus, fmu3_paths, fmu_paths


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


@pytest.fixture(scope="module")
def fmu_versions():
    """The packaged FMUs' paths by FMI version ("2.0", "3.0"); FAILS (never skips) with
    the message that says how to build them."""
    try:
        return {"2.0": fmu_paths(), "3.0": fmu3_paths()}
    except FileNotFoundError as error:
        pytest.fail(str(error), pytrace=False)
