#!/usr/bin/env python3
"""Every citation of a doc section resolves: `docs/FILE.md, "Heading"` in the code, scripts, tests
and docs names a file that exists and a heading in it.

    python3 scripts/check-doc-citations.py [REPO_ROOT]

Code comments cite the docs by section title (a heading changes, the citation breaks silently);
this check, run by the test suite, makes it break loudly. A citation may span comment lines. A
bold run-in paragraph title (**Title.** at a line's start) counts as a heading. The cited text
matches a heading when it is the heading, or a part of it, ignoring case and backticks
(a heading "The closed period (2026-12-04)" is cited as "The closed period"). Exit status 1 lists
each broken citation as FILE:LINE: the citation and what is wrong.
"""
import functools
import os
import re
import sys

ROOT = os.path.abspath(sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), os.pardir))
SOURCE_DIRS = ("apps", "lib", "design", "magnetics", "geometry", "bench", "tests", "scripts", "docs", "examples")
SOURCE_EXT = (".cpp", ".hpp", ".h", ".inc", ".sh", ".py", ".md", ".json", ".txt", ".in")
# docs/X.md, "Heading" | docs/X.md "Heading" | docs/X.md ("Heading" | docs/X.md: "Heading"
CITATION = re.compile(r'docs/([\w./-]+\.md)[,:]?\s*\(?\s*"([^"{};]{2,100}?)"')
BOLD_LEAD = re.compile(r"^\*\*(.+?)\*\*")
COMMENT_LEAD = re.compile(r"^\s*(//+|#+|\*+|--)\s?")


def normalise(text):
    return " ".join(text.replace("`", "").lower().split())


@functools.lru_cache(maxsize=None)
def headings(path):
    found = []
    in_fence = False
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.startswith("```"):
                in_fence = not in_fence
            elif not in_fence and line.startswith("#"):
                found.append(normalise(line.lstrip("#")))
            elif not in_fence and BOLD_LEAD.match(line):  # a run-in paragraph title
                found.append(normalise(BOLD_LEAD.match(line).group(1)))
    return found


def joined_lines(path):
    """The file's text with comment leaders removed and lines joined, and each character's line."""
    text, line_of = [], []
    with open(path, encoding="utf-8", errors="replace") as f:
        for number, line in enumerate(f, 1):
            stripped = COMMENT_LEAD.sub("", line.rstrip("\n")) + " "
            text.append(stripped)
            line_of.extend([number] * len(stripped))
    return "".join(text), line_of


def source_files():
    for top in SOURCE_DIRS:
        for base, dirs, files in os.walk(os.path.join(ROOT, top)):
            dirs[:] = [d for d in dirs if d not in ("out", "build")]
            for name in files:
                if name.endswith(SOURCE_EXT) and name != os.path.basename(__file__):
                    yield os.path.join(base, name)
    yield os.path.join(ROOT, "README.md")


def main():
    broken, checked = [], 0
    for path in source_files():
        text, line_of = joined_lines(path)
        for m in CITATION.finditer(text):
            doc, cited = m.group(1), normalise(m.group(2))
            where = "%s:%d" % (os.path.relpath(path, ROOT), line_of[m.start()])
            target = os.path.join(ROOT, "docs", doc)
            checked += 1
            if not os.path.isfile(target):
                broken.append('%s: docs/%s does not exist (cited with "%s")' % (where, doc, m.group(2)))
            elif not any(cited in h for h in headings(target)):
                broken.append('%s: docs/%s has no heading "%s"' % (where, doc, m.group(2)))
    for line in broken:
        print(line)
    print("%d doc-section citation(s) checked, %d broken" % (checked, len(broken)))
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
