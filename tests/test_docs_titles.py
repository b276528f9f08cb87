"""The site's navigation stays readable: every page of docs/ and docs/notes/ has its own title (the
table of contents shows titles only, so two pages with one title cannot be told apart), no title
carries a tracker number (a page is named by its topic, not by the issue that wrote it), and no page
outside docs/notes/ grows back into a diary (the dated logs live in docs/notes/)."""

import re

from tests.conftest import REPO

PAGES = (
    sorted((REPO / "docs").glob("*.md"))
    + sorted((REPO / "docs" / "layouts").glob("*.md"))
    + sorted((REPO / "docs" / "notes").glob("*.md"))
)


def title(page):
    match = re.search(r"^# (.+)$", page.read_text(), re.MULTILINE)
    return match.group(1).strip() if match else ""


def test_titles_are_distinct_and_name_no_issue():
    titles = {}
    for page in PAGES:
        titles.setdefault(title(page), []).append(page.relative_to(REPO).as_posix())
        assert not re.search(r"\bissues? \d+", title(page), re.IGNORECASE), (
            f"{page.name}: {title(page)}"
        )
    doubles = {t: p for t, p in titles.items() if len(p) > 1}
    assert not doubles, f"pages sharing a title: {doubles}"


def _parameter_tables():
    """docs/parameter_tables.py (the site's build runs it from docs/conf.py; not a package)."""
    import importlib.util

    spec = importlib.util.spec_from_file_location(
        "parameter_tables", REPO / "docs" / "parameter_tables.py"
    )
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


def test_topic_pages_stay_short(tmp_path):
    """No page of the site outside docs/notes/ over 300 lines, counted as the reader gets it: a
    page's ``{include}`` adds the included file's lines; the generated parameter tables
    (docs/_generated/, made at each build) are written here from the code."""
    generated = tmp_path / "_generated"
    _parameter_tables().write_parameter_tables(generated)
    skip = ("notes", "_build", "_generated", "_autosummary")
    pages = [
        p
        for p in sorted((REPO / "docs").rglob("*.md"))
        # the validation summaries too: copies of results/validation/report.md, cut where their
        # header comment says (the full one before its "Model vs model" table)
        if p.relative_to(REPO / "docs").parts[0] not in skip
    ]
    assert len(pages) > 30 and REPO / "docs" / "layouts" / "index.md" in pages
    long = []
    for page in pages:
        text = page.read_text()
        n = len(text.splitlines())
        for target in re.findall(r"^```\{include\} (\S+)$", text, re.MULTILINE):
            included = (
                generated / target.split("/", 1)[1]
                if target.startswith("_generated/")
                else page.parent / target
            )
            assert included.is_file(), f"{page.name} includes {target}: not found"
            n += len(included.read_text().splitlines())
        if n > 300:
            long.append(f"{page.relative_to(REPO / 'docs')} ({n} lines)")
    assert not long, "pages over 300 lines (move the dated record to docs/notes/): " + ", ".join(
        long
    )
