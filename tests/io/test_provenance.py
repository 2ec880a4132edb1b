"""Provenance records: the library versions are those of the installed distributions."""

from __future__ import annotations

from importlib import metadata

import matplotlib  # noqa: F401  (imported: its version comes from the module)

from floebreak.io import provenance


def test_library_versions_are_the_installed_distributions():
    versions = provenance.library_versions()
    assert set(versions) == {"python", *provenance._LIBRARIES}
    for name in provenance._LIBRARIES:
        assert versions[name] == metadata.version(name), name


def test_provenance_carries_versions_and_extra_keys():
    record = provenance.provenance(seed=3)
    assert record["floebreak_version"] == provenance.floebreak_version()
    assert record["libraries"] == provenance.library_versions()
    assert record["seed"] == 3
    record["libraries"]["numpy"] = "changed"  # a copy: the cache is not affected
    assert provenance.library_versions()["numpy"] == metadata.version("numpy")
