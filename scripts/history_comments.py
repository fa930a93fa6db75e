#!/usr/bin/env python3
"""Lists the // comments under lib/ that tell history or measurements instead of what and why.

Comments in the code say what a piece does and why. How it came to be ("was", "used to", "before
issue 31", "hung once") belongs in commit messages, and measured figures ("+1.47%", "6.2x faster",
"41.5 s") in docs/ and BENCHMARKS.md, where they can be re-measured. Flagged here:

  history   past narrative: used to, once did, no longer, since issue N, the old name/default,
            before (the fix|issue|session)
  study     citations of a study's log: docs/studies/... section N, issue N, session
  figure    measured figures: percentages, ratios like 6.2x, timings in s/ms/us/minutes

usage: scripts/history_comments.py [ROOT] [--list] [--max N]
  --list   print every flagged line (path:line [kinds] text)
  --max N  exit 1 when more than N lines are flagged (ctest: Comments.NoMoreHistoryThanTheBudget)
"""
import argparse
import collections
import os
import re
import sys

PATTERNS = {
    "history": re.compile(
        r"\bused to\b|\bno longer\b|\bonce (?:switched|chose|took|ran|read|hung|did)\b|\bhung once\b|"
        r"\bsince issue \d+|\bthe old (?:name|default|rule|code)\b|\bbefore (?:the fix|issue|session|this change)\b|"
        r"\bthe default before\b|\bearlier (?:form|rule|version|code)\b"),
    "study": re.compile(r"docs/studies/\S+ section \d|\bsection \d+(?:\.\d+)? of docs/studies|\bissue \d+|\bsessions?\b"),
    "figure": re.compile(r"[-+]?\b\d+(?:\.\d+)?\s?%|\b\d+(?:\.\d+)?x (?:faster|slower|fewer|more|less|lower|higher)\b|"
                         r"\b\d+(?:\.\d+)? ?(?:s|ms|us|minutes)\b(?![\w(/])"),
}


def flagged_lines(root):
    for folder, _, files in os.walk(root):
        for name in sorted(files):
            if not name.endswith((".h", ".cpp")):
                continue
            path = os.path.join(folder, name)
            with open(path, encoding="utf-8", errors="replace") as f:
                for number, line in enumerate(f, 1):
                    comment = line.split("//", 1)
                    if len(comment) < 2 or '"' in comment[0]:   # no comment, or "//" inside a string
                        continue
                    kinds = [kind for kind, pattern in PATTERNS.items() if pattern.search(comment[1])]
                    if kinds:
                        yield path, number, kinds, comment[1].strip()


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("root", nargs="?", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "lib"))
    parser.add_argument("--list", action="store_true")
    parser.add_argument("--max", type=int, default=None)
    args = parser.parse_args()
    rows = list(flagged_lines(args.root))
    per_file = collections.Counter(os.path.relpath(r[0], args.root) for r in rows)
    per_kind = collections.Counter(k for r in rows for k in r[2])
    if args.list:
        for path, number, kinds, text in rows:
            print(f"{os.path.relpath(path, args.root)}:{number} [{','.join(kinds)}] {text[:140]}")
    print(f"history_comments: {len(rows)} flagged lines in {len(per_file)} files "
          f"({', '.join(f'{k} {per_kind[k]}' for k in PATTERNS)})")
    for path, n in per_file.most_common(10):
        print(f"  {n:3d} {path}")
    if args.max is not None and len(rows) > args.max:
        print(f"history_comments: {len(rows)} > the budget of {args.max}: say what and why in the comment, move the "
              f"history to the commit message and the figures to docs/ (list them with --list)", file=sys.stderr)
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
