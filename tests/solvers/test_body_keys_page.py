"""The reference page of the own-robot case file (docs/own_robot_keys.md) lists every section and
key of :data:`lcefem.solvers.problems.body_case.SCHEMA` (the table the checks read) with its unit,
and names no key the schema does not have."""

import re

from lcefem.solvers.problems.body_case import SCHEMA
from tests.conftest import REPO


def page_sections():
    """{section: {key: unit}} of the page's tables (``## `[section]``` / ``## `[[section]]```)."""
    sections, current = {}, None
    for line in (REPO / "docs" / "own_robot_keys.md").read_text().splitlines():
        heading = re.match(r"^## `\[\[?(\w+)\]\]?`", line)
        if heading:
            current = sections.setdefault(heading.group(1), {})
            continue
        row = re.match(r"^\| `(\w+)` \| [^|]* \| ([^|]*) \|", line)
        if row and current is not None:
            current[row.group(1)] = row.group(2).strip()
    return sections


def test_every_schema_key_is_on_the_page_with_its_unit():
    page = page_sections()
    for section, keys in SCHEMA.items():
        assert section in page, f"[{section}] is not on docs/own_robot_keys.md"
        for key, spec in keys.items():
            assert key in page[section], f"[{section}] {key} is not on docs/own_robot_keys.md"
            assert page[section][key] == spec[1], (
                f"[{section}] {key}: unit {page[section][key]!r} != {spec[1]!r}"
            )
        extra = set(page[section]) - set(keys)
        assert not extra, f"[{section}] keys on the page but not in the schema: {sorted(extra)}"
