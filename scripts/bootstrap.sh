#!/usr/bin/env bash
# Create .venv from a Python >= 3.12 that really runs, and install lcefem with pinned dependencies.
# Usage: scripts/bootstrap.sh [docs]   (idempotent: does nothing when .venv is up to date;
#        "docs" also installs the pinned documentation group, make docs)
set -euo pipefail
cd "$(dirname "$0")/.."
VENV=.venv
STAMP=$VENV/.lcefem-installed
DOCS_STAMP=$VENV/.lcefem-docs-installed
WANT_DOCS=0
[ "${1:-}" = docs ] && WANT_DOCS=1

docs_ready() {  # the docs group is installed and not older than the pins
    [ "$WANT_DOCS" = 0 ] || { [ -f "$DOCS_STAMP" ] && [ "$DOCS_STAMP" -nt pyproject.toml ] \
        && [ "$DOCS_STAMP" -nt requirements.lock ]; }
}

runs_312() {  # true when "$1" is an interpreter that starts and is >= 3.12
    "$1" -c 'import sys; sys.exit(0 if sys.version_info >= (3, 12) else 1)' >/dev/null 2>&1
}

find_python() {
    local c candidates=()
    [ -n "${LCEFEM_PYTHON:-}" ] && candidates+=("$LCEFEM_PYTHON")
    # pyenv shims on PATH may refuse to run a version that is not selected: ask pyenv for real paths.
    if command -v pyenv >/dev/null 2>&1; then
        local root; root=$(pyenv root)
        for c in "$root"/versions/3.12*/bin/python3 "$root"/versions/3.13*/bin/python3; do
            [ -x "$c" ] && candidates+=("$c")
        done
    fi
    candidates+=(python3.12 python3.13 python3 /usr/bin/python3.12 /usr/bin/python3.13)
    for c in "${candidates[@]}"; do
        if command -v "$c" >/dev/null 2>&1 && runs_312 "$c"; then
            command -v "$c"; return 0
        fi
    done
    return 1
}

if [ -f "$STAMP" ] && [ "$STAMP" -nt pyproject.toml ] && [ "$STAMP" -nt requirements.lock ] \
        && "$VENV/bin/python" -c 'import lcefem.models' >/dev/null 2>&1; then
    docs_ready && exit 0
    "$VENV/bin/python" -m pip install --quiet -c requirements.lock -e ".[test,docs]"
    touch "$DOCS_STAMP"
    echo "lcefem: documentation tools ready in $VENV"
    exit 0
fi

if [ ! -x "$VENV/bin/python" ] || ! runs_312 "$VENV/bin/python"; then
    PY=$(find_python) || {
        echo "lcefem: no Python >= 3.12 found that runs. Install one (e.g. 'pyenv install 3.12' or" \
             "Debian's python3.12 with python3.12-venv), or set LCEFEM_PYTHON=/path/to/python3.12." >&2
        exit 1
    }
    echo "lcefem: creating $VENV with $PY ($("$PY" --version 2>&1))"
    rm -rf "$VENV"
    "$PY" -m venv "$VENV"
fi
"$VENV/bin/python" -m pip install --quiet --upgrade "pip==26.3"
if [ "$WANT_DOCS" = 1 ]; then
    "$VENV/bin/python" -m pip install --quiet -c requirements.lock -e ".[test,docs]"
    touch "$DOCS_STAMP"
else
    "$VENV/bin/python" -m pip install --quiet -c requirements.lock -e ".[test]"
fi
touch "$STAMP"
echo "lcefem: environment ready in $VENV"
