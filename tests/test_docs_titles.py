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


def test_topic_pages_stay_short():
    # the generated validation summaries are copies of a report, not written pages
    long = [
        f"{p.name} ({n} lines)"
        for p in sorted((REPO / "docs").glob("*.md"))
        + sorted((REPO / "docs" / "layouts").glob("*.md"))
        if not p.name.startswith("validation_summary_")
        and (n := len(p.read_text().splitlines())) > 300
    ]
    assert not long, "pages over 300 lines (move the dated record to docs/notes/): " + ", ".join(
        long
    )
