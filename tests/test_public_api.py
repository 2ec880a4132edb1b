"""The curated public API of `import floebreak` (docs/api.md)."""

from __future__ import annotations

from pathlib import Path

import floebreak

API_DOC = Path(__file__).resolve().parents[1] / "docs" / "api.md"


def test_every_public_name_resolves_to_the_module_docs_api_names():
    # docs/api.md lists each name with the module that defines it; a renamed or moved function fails here
    text = API_DOC.read_text(encoding="utf-8")
    for name in floebreak.__all__:
        value = getattr(floebreak, name)
        assert value is not None
        assert f"`{name}`" in text, f"{name} is not described in docs/api.md"


def test_the_failure_registry_is_the_public_one():
    from floebreak.failure import registry

    assert floebreak.register_mode is registry.register_mode
    assert {"bending", "cracking", "local_cracking", "rotation", "none"} <= set(floebreak.mode_names())
