#!/usr/bin/env bash
# The formatting of the tree (issue 48, item 6), run once after scripts/dev/rooms.py:
#     scripts/dev/tidy.sh              (RUFF=path/to/ruff, PYTHON=path/to/python3.12 to override)
# 1. ruff format: line length 100, quotes as written ([tool.ruff] and [tool.ruff.format] in
#    pyproject.toml); the formatter keeps the syntax tree;
# 2. the import order (ruff's I rules: dolfinx_solver, mpi4py and petsc4py in a section of their own
#    before the third-party imports, dolfinx and its companions after them, lcefem last);
# 3. scripts/dev/rewrap.py: the comments, docstrings and string literals the formatter cannot split,
#    each file written only if its syntax tree is unchanged (docstrings: the same words), then the
#    formatter again for the split literals;
# 4. selects I (and E501, once no line is past 100) in pyproject.toml when the tree passes it;
# 5. counts what E501 remains, by kind, and runs ruff check with the configured rules.
# Running it again changes nothing.
set -euo pipefail
cd "$(dirname "$0")/../.."
RUFF=${RUFF:-.venv/bin/ruff}
PYTHON=${PYTHON:-.venv/bin/python}  # 3.12: tokenize reads inside f-strings

"$RUFF" format --quiet .
"$RUFF" check --select I --fix --quiet . || true
"$PYTHON" scripts/dev/rewrap.py
"$RUFF" format --quiet .

select_if_clean() {  # add rule $1 to [tool.ruff.lint] select when the tree passes it
    if "$RUFF" check --select "$1" --quiet . >/dev/null 2>&1; then
        "$PYTHON" - "$1" <<'EOF'
import pathlib, re, sys
rule, path = sys.argv[1], pathlib.Path("pyproject.toml")
text = path.read_text()
m = re.search(r'^select = \[(.*)\]$', text, re.M)
if m and f'"{rule}"' not in m.group(1):
    text = text[:m.end(1)] + f', "{rule}"' + text[m.end(1):]
    path.write_text(text)
    print(f"tidy: {rule} selected in pyproject.toml")
EOF
    else
        echo "tidy: $1 not selected: the tree does not pass it yet"
    fi
}
select_if_clean I
select_if_clean E501

{ "$RUFF" check --select E501 --output-format concise . 2>/dev/null || true; } \
    | "$PYTHON" scripts/dev/rewrap.py --report
"$RUFF" check .
