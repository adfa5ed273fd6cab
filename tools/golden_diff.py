#!/usr/bin/env python3
"""Compares two tools/golden.sh output folders file by file, timings removed.

    tools/golden_diff.py OLD_DIR NEW_DIR

JSON documents are compared as data with every key naming a time (seconds, elapsed, wall,
timestamp, started, finished, evaluations_per_second) dropped; other text files line by line with
numbers followed by a time unit (" s", " ms", "s/") masked. Prints each file that differs with its
first differing entries, and the files present on one side only. Exit 0 when nothing differs.
"""
import json
import os
import re
import sys

TIME_KEY = re.compile(r"(second|elapsed|wall|timestamp|started|finished|per_second|time_s$|_ms$)")
TIME_TEXT = re.compile(r"[-+0-9.eE]+( ?(s|ms|min)\b|/s\b)")
SKIP = re.compile(r"(\.svg|\.png|\.gp|\.log)$")


def strip(node):
    if isinstance(node, dict):
        return {k: strip(v) for k, v in node.items() if not TIME_KEY.search(k)}
    if isinstance(node, list):
        return [strip(v) for v in node]
    return node


def json_diff(a, b, path=""):
    if type(a) is not type(b):
        yield f"{path}: {json.dumps(a)[:80]} != {json.dumps(b)[:80]}"
    elif isinstance(a, dict):
        for k in sorted(set(a) | set(b)):
            if k not in a:
                yield f"{path}.{k}: new key"
            elif k not in b:
                yield f"{path}.{k}: removed key"
            else:
                yield from json_diff(a[k], b[k], f"{path}.{k}")
    elif isinstance(a, list):
        if len(a) != len(b):
            yield f"{path}: {len(a)} entries != {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            yield from json_diff(x, y, f"{path}[{i}]")
    elif a != b:
        yield f"{path}: {a!r} != {b!r}"


TIME_HEADER = re.compile(r"^(seconds|time|wall|wall time|\[s\]|time \[s\])$", re.I)
HTML_CELL = re.compile(r"<t([hd])>(.*?)</t[hd]>")


def mask_columns(cells, columns):
    return [("<t>" if i in columns else c) for i, c in enumerate(cells)]


def text_lines(path):
    """Lines with times masked: numbers with a time unit, and table columns headed by a time."""
    out, md_columns, html_columns, csv_columns = [], set(), set(), set()
    with open(path, encoding="utf-8", errors="replace") as f:
        for number, line in enumerate(f):
            line = line.rstrip("\n")
            if path.endswith(".csv"):  # a CSV table: its columns headed by a time (batch's seconds)
                cells = line.split(",")
                if number == 0:
                    csv_columns = {i for i, c in enumerate(cells) if TIME_HEADER.match(c)}
                else:
                    line = ",".join(mask_columns(cells, csv_columns))
            if line.startswith("|"):
                cells = [c.strip() for c in line.strip("|").split("|")]
                if any(TIME_HEADER.match(c) for c in cells):
                    md_columns = {i for i, c in enumerate(cells) if TIME_HEADER.match(c)}
                else:
                    line = "|".join(mask_columns(cells, md_columns))
            else:
                md_columns = md_columns if line == "" else set()
            cells = HTML_CELL.findall(line)
            if cells and cells[0][0] == "h":
                html_columns = {i for i, (_, c) in enumerate(cells) if TIME_HEADER.match(c)}
            elif cells and html_columns:
                line = "".join(mask_columns([c for _, c in cells], html_columns))
            out.append(TIME_TEXT.sub("<t>", line))
    return out


def compare(old, new):
    if old.endswith(".json"):
        try:
            with open(old) as f:
                a = strip(json.load(f))
            with open(new) as f:
                b = strip(json.load(f))
            return list(json_diff(a, b))
        except ValueError:
            pass
    a, b = text_lines(old), text_lines(new)
    out = [f"line {i + 1}: {x[:100]!r} != {y[:100]!r}" for i, (x, y) in enumerate(zip(a, b)) if x != y]
    if len(a) != len(b):
        out.append(f"{len(a)} lines != {len(b)}")
    return out


def files(root):
    out = set()
    for d, _, names in os.walk(root):
        for n in names:
            rel = os.path.relpath(os.path.join(d, n), root)
            if not SKIP.search(rel):
                out.add(rel)
    return out


def main():
    old_root, new_root = sys.argv[1], sys.argv[2]
    old, new = files(old_root), files(new_root)
    differ = 0
    for rel in sorted(old ^ new):
        print(f"only in {'old' if rel in old else 'new'}: {rel}")
        differ += 1
    for rel in sorted(old & new):
        d = compare(os.path.join(old_root, rel), os.path.join(new_root, rel))
        if d:
            differ += 1
            print(f"{rel}: {len(d)} differences")
            for line in d[:6]:
                print(f"    {line}")
    print(f"golden_diff: {len(old & new)} files compared, {differ} differ")
    return 1 if differ else 0


if __name__ == "__main__":
    sys.exit(main())
