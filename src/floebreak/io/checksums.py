"""The checksum a JSON document carries of itself (a run's ``summary.json``).

A file cannot hold the SHA-256 of its own bytes, so the document records the SHA-256 of its *content*: the
canonical JSON (sorted keys, no spaces, ASCII) of the document without the checksum's own key. Reading the
file back (``json.loads``) and hashing again gives the same value, whatever its indentation; any edited value
gives another. A resumed study trusts a run's summary only when it matches (`floebreak.studies.runner`).
"""

from __future__ import annotations

import hashlib
import json
from collections.abc import Mapping
from typing import Any

SUMMARY_CHECKSUM_KEY = "summary_sha256"


def document_sha256(document: Mapping[str, Any], key: str = SUMMARY_CHECKSUM_KEY) -> str:
    """SHA-256 (hex) of the canonical JSON of `document` without `key`."""
    content = {name: value for name, value in document.items() if name != key}
    text = json.dumps(content, sort_keys=True, separators=(",", ":"), ensure_ascii=True)
    return hashlib.sha256(text.encode("ascii")).hexdigest()


def with_checksum(document: Mapping[str, Any], key: str = SUMMARY_CHECKSUM_KEY) -> dict[str, Any]:
    """`document` with its checksum (`document_sha256`) under `key`, last."""
    content = {name: value for name, value in document.items() if name != key}
    return {**content, key: document_sha256(content, key)}


def checksum_matches(document: Mapping[str, Any], key: str = SUMMARY_CHECKSUM_KEY) -> bool:
    """Whether `document` carries its own checksum under `key` and it matches its content."""
    return document.get(key) == document_sha256(document, key)
