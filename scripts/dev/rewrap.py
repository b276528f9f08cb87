"""Rewrap what the formatter leaves past the line limit (issue 48, item 6): comments, docstrings and
long string literals, without changing the program.

    python3 scripts/dev/rewrap.py [--limit 100] [--check] [FILE ...]   (default: every tracked .py)

Run by scripts/dev/tidy.sh after ``ruff format``. Line by line, read with tokenize:

* a comment alone on its line: the words past the limit move to the next comment line of the same
  paragraph (same indentation and marker, ``#`` or ``#:``) or to a new one; pragmas (noqa, type:,
  fmt:) and comments without a space to break at are left;
* a docstring's prose line (at the docstring's own indentation, or a bullet and its continuation):
  the same, within the docstring; the summary (first) line, indented literal blocks and usage
  lines are left, since a command's help and the rendered page show them as written;
* a string literal inside brackets (plain or raw, single-quoted): split at a space into adjacent
  literals, which the parser joins back into the same constant.

Each file is written only when its syntax tree is the same as before: identical, but for the
docstrings, whose words (split on whitespace) must be identical. Otherwise the file is left and
named. ``--check`` writes nothing and prints what would change.
"""

from __future__ import annotations

import argparse
import ast
import io
import pathlib
import re
import subprocess
import sys
import tokenize

ROOT = pathlib.Path(__file__).resolve().parents[2]
PRAGMA = re.compile(r"#\s*(noqa|type:|fmt:|pragma|ruff:|pylint:|isort:)")
BULLET = re.compile(r"(\* |- |\d+\. |\(\w\) )")


def docstring_owners(tree: ast.AST):
    """(docstring Constant, the module, class or function it documents) of every docstring."""
    for node in ast.walk(tree):
        if isinstance(node, (ast.Module, ast.ClassDef, ast.FunctionDef, ast.AsyncFunctionDef)):
            body = node.body
            if (
                body
                and isinstance(body[0], ast.Expr)
                and isinstance(body[0].value, ast.Constant)
                and isinstance(body[0].value.value, str)
            ):
                yield body[0].value, node


def docstring_nodes(tree: ast.AST):
    for node, _ in docstring_owners(tree):
        yield node


def normalized(source: str) -> str:
    """The syntax tree of ``source`` with every docstring's whitespace collapsed."""
    tree = ast.parse(source)
    for node in docstring_nodes(tree):
        node.value = " ".join(node.value.split())
    return ast.dump(tree)


def docstring_rows(source: str) -> dict[int, tuple[int, int, int, bool]]:
    """{row: (base indentation, first row, last row, a module's)} of every docstring row
    (1-based)."""
    out = {}
    lines = source.split("\n")
    for node, owner in docstring_owners(ast.parse(source)):
        rows = range(node.lineno + 1, node.end_lineno + 1)
        base = min(
            (
                len(lines[r - 1]) - len(lines[r - 1].lstrip(" "))
                for r in rows
                if lines[r - 1].strip()
            ),
            default=None,
        )
        first = lines[node.lineno - 1]
        if base is None:  # a one-line docstring: its continuation aligns with the quotes
            base = len(first) - len(first.lstrip(" "))
        out.update(
            {
                r: (base, node.lineno, node.end_lineno, isinstance(owner, ast.Module))
                for r in range(node.lineno, node.end_lineno + 1)
            }
        )
    return out


def split_at(text: str, width: int) -> tuple[str, str] | None:
    """(head, tail) with head <= width, cut at the last space; None if there is none."""
    if len(text) <= width:
        return None
    cut = text.rfind(" ", 0, width + 1)
    while cut > 0 and text[cut - 1] == " ":
        cut -= 1
    if cut <= 0:
        return None
    return text[:cut], text[cut:].lstrip(" ")


def carry(lines: list[str], i: int, prefix: str, cont_prefix: str, limit: int, joinable) -> bool:
    """Cut line ``i`` (``prefix`` + text) at the limit; the tail joins line i+1 when
    ``joinable(line)`` says it continues the paragraph (and it then still fits or is cut in its
    turn), or becomes a new line ``cont_prefix`` + tail. True if something changed."""
    line = lines[i]
    text = line[len(prefix) :]
    cut = split_at(text, limit - len(prefix))
    if not cut:
        return False
    head, tail = cut
    lines[i] = prefix + head
    nxt = lines[i + 1] if i + 1 < len(lines) else None
    if nxt is not None and joinable(nxt):
        lines[i + 1] = cont_prefix + tail + " " + nxt[len(cont_prefix) :]
    else:
        lines.insert(i + 1, cont_prefix + tail)
    return True


def rewrap_comments(source: str, limit: int) -> str:
    lines = source.split("\n")
    changed = True
    while changed:  # each cut may add a line: read the comments again
        changed = False
        for row in sorted(comment_rows("\n".join(lines))):
            i = row - 1
            line = lines[i]
            m = re.match(r"([ \t]*)(#:? )(.*)$", line)
            if len(line) <= limit or not m or PRAGMA.search(line):
                continue
            prefix = m.group(1) + m.group(2)

            def joinable(nxt, prefix=prefix):
                rest = nxt[len(prefix) :]
                return (
                    nxt.startswith(prefix)
                    and rest[:1].strip()
                    and not BULLET.match(rest)
                    and not PRAGMA.search(nxt)
                    and not rest.startswith(("#", " "))
                )

            if carry(lines, i, prefix, prefix, limit, joinable):
                changed = True
                break
    return "\n".join(lines)


def rewrap_docstrings(source: str, limit: int) -> str:
    lines = source.split("\n")
    changed = True
    while changed:  # each cut may add a line: read the docstrings again
        changed = False
        doc = docstring_rows("\n".join(lines))
        for n in sorted(doc):
            i = n - 1
            line = lines[i]
            base, first, last, module = doc[n]
            if len(line) <= limit:
                continue
            indent = len(line) - len(line.lstrip(" "))
            rest = line[indent:]
            if n == first:
                if module:  # a command's --help shows its module's first line as written
                    continue
                m = re.match(r"[rRuU]?(\"\"\"|\'\'\')", rest)
                if not m:
                    continue
                prefix, cont = " " * indent + m.group(0), " " * base
            elif rest.startswith((">>>", "..", "|", "+-", "=")):
                continue
            elif BULLET.match(rest) and indent == base:
                prefix, cont = " " * indent, " " * (indent + len(BULLET.match(rest).group(1)))
            elif indent == base or _continues_bullet(lines, i, base, indent):
                prefix = cont = " " * indent
            else:
                continue  # a literal block, a usage line, a table: as written

            def joinable(nxt, cont=cont, n=n, last=last):
                r = nxt[len(cont) :]
                return (
                    n + 1 <= last
                    and nxt.startswith(cont)
                    and r[:1].strip()
                    and not BULLET.match(r)
                    and not r.startswith(('"""', "'''", ">>>", "..", ":"))
                )

            if carry(lines, i, prefix, cont, limit, joinable):
                changed = True
                break
    return "\n".join(lines)


def _continues_bullet(lines: list[str], i: int, base: int, indent: int) -> bool:
    """Line i is the continuation of a bullet item at indentation ``base``."""
    for k in range(i - 1, -1, -1):
        prev = lines[k]
        if not prev.strip():
            return False
        pin = len(prev) - len(prev.lstrip(" "))
        m = BULLET.match(prev.lstrip(" "))
        if pin == base and m:
            return indent == base + len(m.group(1))
        if pin != indent:
            return False
    return False


def rewrap_strings(source: str, limit: int) -> str:
    """Long single-quoted literals inside brackets split at a space into adjacent literals."""
    lines = source.split("\n")
    edits = []  # (row, col_start, col_end, replacement)
    depth = 0
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.OP and tok.string in "([{":
            depth += 1
        elif tok.type == tokenize.OP and tok.string in ")]}":
            depth -= 1
        if tok.type != tokenize.STRING or depth == 0 or tok.start[0] != tok.end[0]:
            continue
        row, col = tok.start
        if len(lines[row - 1]) <= limit:
            continue
        m = re.match(r"([rR]?)(['\"])(.*)\2$", tok.string, re.S)
        if not m or m.group(3).startswith(m.group(2) * 2):
            continue
        pre, q, body = m.groups()
        pieces, width = [], max(limit - col - 2 - len(pre) - 1, 20)
        while len(body) > width:
            cut = body.rfind(" ", 0, width)
            if cut <= 0:
                break
            pieces.append(body[: cut + 1])
            body = body[cut + 1 :]
            width = max(limit - col - 2 - len(pre) - 1, 20)
        if not pieces:
            continue
        pieces.append(body)
        sep = "\n" + " " * col
        edits.append((row, col, tok.end[1], sep.join(f"{pre}{q}{p}{q}" for p in pieces)))
    for row, start, end, new in sorted(edits, reverse=True):
        line = lines[row - 1]
        lines[row - 1] = line[:start] + new + line[end:]
    return "\n".join(lines)


def rewrap_fstrings(source: str, limit: int) -> str:
    """Long one-line f-strings inside brackets split at a space of their literal text into adjacent
    literals (a piece without a replacement field loses its ``f``), which the parser joins back."""
    lines = source.split("\n")
    toks = list(tokenize.generate_tokens(io.StringIO(source).readline))
    edits, depth, k = [], 0, 0
    while k < len(toks):
        tok = toks[k]
        if tok.type == tokenize.OP and tok.string in "([{":
            depth += 1
        elif tok.type == tokenize.OP and tok.string in ")]}":
            depth -= 1
        if tok.type != getattr(tokenize, "FSTRING_START", None):
            k += 1
            continue
        # the f-string's tokens up to its own end (nested f-strings included)
        level, j, cuts = 0, k + 1, []
        nest = 1
        while nest:
            t = toks[j]
            if t.type == tokenize.FSTRING_START:
                nest += 1
            elif t.type == tokenize.FSTRING_END:
                nest -= 1
            elif t.type == tokenize.OP and t.string == "{":
                level += 1
            elif t.type == tokenize.OP and t.string == "}":
                level -= 1
            elif (
                t.type == tokenize.FSTRING_MIDDLE
                and level == 0
                and nest == 1
                and t.start[0] == t.end[0]
            ):
                text = lines[t.start[0] - 1][t.start[1] : t.end[1]]
                cuts += [t.start[1] + i + 1 for i, ch in enumerate(text) if ch == " "]
            j += 1
        end = toks[j - 1]
        row, col = tok.start
        line = lines[row - 1]
        quote = tok.string[-1]
        simple = (
            end.start[0] == row
            and len(line) > limit
            and depth > 0
            and len(tok.string) <= 3
            and "{{" not in line[col : end.end[1]]
            and "}}" not in line[col : end.end[1]]
        )
        if simple:
            body_start, body_end = col + len(tok.string), end.start[1]
            pieces, start, room = [], body_start, limit - 1
            for c in sorted(set(cuts)):
                if c >= body_end:
                    break
                nxt = [d for d in cuts if c < d < body_end]
                if c <= room and (not nxt or min(nxt) > room):
                    pieces.append((start, c))
                    start, room = c, c + (limit - 1 - col - len(tok.string))
            if pieces:
                pieces.append((start, body_end))
                out = []
                for a, b in pieces:
                    piece = line[a:b]
                    pre = (
                        tok.string[:-1]
                        if "{" in piece
                        else tok.string[:-1].replace("f", "").replace("F", "")
                    )
                    out.append(f"{pre}{quote}{piece}{quote}")
                edits.append((row, col, end.end[1], ("\n" + " " * col).join(out)))
        k = j
    for row, start, stop, new in sorted(edits, reverse=True):
        line = lines[row - 1]
        lines[row - 1] = line[:start] + new + line[stop:]
    return "\n".join(lines)


def comment_rows(source: str) -> set[int]:
    """Rows (1-based) holding a comment and nothing else."""
    rows = set()
    for tok in tokenize.generate_tokens(io.StringIO(source).readline):
        if tok.type == tokenize.COMMENT and not tok.line[: tok.start[1]].strip():
            rows.add(tok.start[0])
    return rows


def rewrap(source: str, limit: int) -> str:
    out = rewrap_comments(source, limit)
    out = rewrap_docstrings(out, limit)
    out = rewrap_strings(out, limit)
    return rewrap_fstrings(out, limit)


def kind(source: str, row: int, cache: dict) -> str:
    """What makes line ``row`` long: comment, inline comment, docstring, module summary, string,
    code."""
    if "tokens" not in cache:
        cache["tokens"] = list(tokenize.generate_tokens(io.StringIO(source).readline))
        cache["doc"] = docstring_rows(source)
    doc = cache["doc"]
    if row in doc:
        base, first, last, module = doc[row]
        if row == first and module:
            return "module summary line (a command's --help)"
        return (
            "docstring: summary line"
            if row == first
            else "docstring: literal block, table or usage"
        )
    for tok in cache["tokens"]:
        if tok.start[0] <= row <= tok.end[0]:
            if tok.type == tokenize.COMMENT:
                return "inline comment" if tok.line[: tok.start[1]].strip() else "comment"
            if tok.type == tokenize.STRING or tok.type == getattr(tokenize, "FSTRING_START", None):
                if tok.type != tokenize.STRING or tok.string[:1] in "fF":
                    return "f-string"
                return "string literal"
    return "code"


def report(lines: list[str]) -> str:
    """Counts by kind of ``ruff check --select E501 --output-format concise`` lines."""
    counts: dict[str, int] = {}
    caches: dict[str, dict] = {}
    sources: dict[str, str] = {}
    for line in lines:
        m = re.match(r"(.+?):(\d+):\d+: E501", line)
        if not m:
            continue
        name, row = m.group(1), int(m.group(2))
        if name not in sources:
            sources[name] = pathlib.Path(name).read_text(encoding="utf-8")
        k = kind(sources[name], row, caches.setdefault(name, {}))
        counts[k] = counts.get(k, 0) + 1
    total = sum(counts.values())
    return f"E501 left: {total}" + "".join(
        f"\n  {n:5d}  {k}" for k, n in sorted(counts.items(), key=lambda kv: -kv[1])
    )


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("files", nargs="*")
    parser.add_argument("--limit", type=int, default=100)
    parser.add_argument("--check", action="store_true")
    parser.add_argument(
        "--report",
        action="store_true",
        help="read ruff's E501 findings (--output-format concise) on stdin, count them by kind",
    )
    args = parser.parse_args(argv)
    if args.report:
        print(report(sys.stdin.read().splitlines()))
        return 0
    files = args.files or [
        str(ROOT / f)
        for f in subprocess.run(
            ["git", "ls-files", "*.py"], cwd=ROOT, capture_output=True, text=True, check=True
        ).stdout.split()
    ]
    changed, refused = [], []
    for name in files:
        path = pathlib.Path(name)
        source = path.read_text(encoding="utf-8")
        new = rewrap(source, args.limit)
        if new == source:
            continue
        try:
            same = normalized(new) == normalized(source)
        except SyntaxError:
            same = False
        if not same:
            refused.append(name)
            continue
        changed.append(name)
        if not args.check:
            path.write_text(new, encoding="utf-8")
    print(f"rewrap: {len(changed)} files {'to rewrap' if args.check else 'rewrapped'}")
    if refused:
        print(
            "rewrap: left as they were (the syntax tree would change):\n  " + "\n  ".join(refused)
        )
    return 0


if __name__ == "__main__":
    sys.exit(main())
