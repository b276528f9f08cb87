"""The user's documentation keeps its promises: the README is a short entry page whose links stay
inside the repository, every docs page has a title and valid local links, and every example is
rendered in the site and executed by a test. (The site itself is built with warnings as errors by
``make docs``, which .ci/run runs after the test suite: a full Sphinx build takes about a
minute.)"""

import re
import tomllib

import pytest

from tests.conftest import REPO

LINK = re.compile(r"\[[^\]]*\]\(([^)\s]+)\)")
#: the topic pages and the pages of a topic's own folder (docs/layouts/: one page per layout type)
DOCS = sorted((REPO / "docs").glob("*.md")) + sorted((REPO / "docs" / "layouts").glob("*.md"))


def local_links(path):
    """The links of a Markdown file that are not web addresses or in-page anchors."""
    for target in LINK.findall(path.read_text()):
        if re.match(r"[a-z]+://", target) or target.startswith(("#", "mailto:")):
            continue
        yield target.split("#")[0]


def test_readme_is_an_entry_page():
    text = (REPO / "README.md").read_text()
    lines = text.splitlines()
    assert len(lines) <= 250
    first_screen = "\n".join(lines[:45])
    for needed in ("make validate", "make test", "lcefem run strip", "docs/"):
        assert needed in first_screen, needed
    # no tracker numbers and no dated measurement log (those live in docs/)
    assert not re.search(r"\bissues? \d+", text, re.IGNORECASE)
    assert not re.search(r"\b20\d\d-\d\d-\d\d\b", text)


@pytest.mark.parametrize(
    "page", [REPO / "README.md", REPO / "CHANGELOG.md", *DOCS], ids=lambda p: p.name
)
def test_local_links_resolve_inside_the_repository(page):
    for target in local_links(page):
        resolved = (page.parent / target).resolve()
        assert resolved.is_relative_to(REPO), f"{page.name}: {target} leaves the repository"
        assert resolved.exists(), f"{page.name}: {target} does not exist"
    assert "shared/" not in page.read_text(), f"{page.name} names a folder outside the repository"


@pytest.mark.parametrize("page", DOCS, ids=lambda p: p.relative_to(REPO).as_posix())
def test_every_page_has_a_title(page):
    # the site's table of contents takes each page's first level-1 heading as its title
    assert re.search(r"^# \S", page.read_text(), re.MULTILINE), f"{page.name} has no '# Title'"


def test_every_example_is_rendered_and_executed():
    examples = sorted((REPO / "docs" / "examples").glob("*.py"))
    assert examples
    page = (REPO / "docs" / "examples.md").read_text()
    tests = "\n".join(
        p.read_text() for p in (REPO / "tests").rglob("test_*.py") if p.name != "test_docs.py"
    )
    for example in examples:
        assert f"```{{literalinclude}} examples/{example.name}" in page, example.name
        assert example.name in tests, f"no test runs docs/examples/{example.name}"


def test_the_docs_build_excludes_what_is_not_a_page():
    conf = (REPO / "docs" / "conf.py").read_text()
    for folder in ("_build", "experiments", "convergence"):
        assert f'"{folder}"' in conf
    assert ":glob:" in (REPO / "docs" / "index.md").read_text()


def test_licence_and_citation_are_present():
    assert "MIT License" in (REPO / "LICENSE").read_text()
    citation = (REPO / "CITATION.cff").read_text()
    assert "cff-version: 1.2.0" in citation and "license: MIT" in citation
    # the same licence as the distribution declares
    assert tomllib.loads((REPO / "pyproject.toml").read_text())["project"]["license"] == "MIT"
