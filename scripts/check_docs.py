#!/usr/bin/env python3
"""Runs the worked examples of massid's docs and checks their printed output.

A fenced block preceded by the line `<!-- run -->` is run: in a ```console
block each `$ ` line (with its `\\` continuation lines) is a command, and the
lines after it up to the next command are what it prints; a ```sh block is run
whole and its output is not shown. The blocks of one file run in order in one
scratch directory (a file a block writes is there for the next), where
`examples/` and `tests/` link to the repository's and `massid` is the program
under test (--massid).

A block's printed lines must appear in the command's output in order (stdout
and stderr each in order; whitespace runs compare as one space); a line `...`
stands for any number of lines the document leaves out, and `...` within a
line for any text (a cut expression, a time that varies). So a document may
show a part of the output, never output the program does not print.

  check_docs.py --massid BUILD/massid [--update] FILE.md ...

--update rewrites the printed lines of each command from what the program
printed: every line when the block leaves none out, else the lines that begin
with the same first word as a shown line (a parameter table's p1, p24 ...),
with `...` kept where the document had it. Review the diff.
"""
import argparse
import os
import re
import shutil
import subprocess
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def blocks(text):
    """(start, end, kind) of each fenced block marked `<!-- run -->`: lines [start, end)."""
    lines = text.split("\n")
    out = []
    i = 0
    while i < len(lines):
        if lines[i].strip() == "<!-- run -->" and i + 1 < len(lines):
            m = re.match(r"^```(console|sh)\s*$", lines[i + 1])
            if not m:
                raise SystemExit(f"line {i + 1}: <!-- run --> must precede a ```console or ```sh block")
            j = i + 2
            while j < len(lines) and lines[j].strip() != "```":
                j += 1
            out.append((i + 2, j, m.group(1)))
            i = j
        i += 1
    return lines, out


def commands(body):
    """[(command text, [printed lines], index of the first printed line)]."""
    out = []
    k = 0
    while k < len(body):
        if not body[k].startswith("$ "):
            raise SystemExit(f"expected a '$ ' command, got: {body[k]}")
        cmd = body[k][2:]
        while cmd.endswith("\\") and k + 1 < len(body):
            k += 1
            cmd = cmd[:-1] + " " + body[k].strip()
        k += 1
        first = k
        shown = []
        while k < len(body) and not body[k].startswith("$ "):
            shown.append(body[k])
            k += 1
        out.append((cmd, shown, first))
    return out


def norm(line):
    return " ".join(line.split())


def run(cmd, cwd, env):
    p = subprocess.run(["bash", "-c", cmd], cwd=cwd, env=env, capture_output=True, text=True)
    return p.stdout.splitlines(), p.stderr.splitlines(), p.returncode


def check(shown, out, err):
    """The first shown line not found in order, or None."""
    at = {"out": 0, "err": 0}
    streams = {"out": [norm(x) for x in out], "err": [norm(x) for x in err]}
    for line in shown:
        if line.strip() in ("...", ""):
            continue
        want = norm(line)
        # "..." inside a line stands for any text (a cut expression, a time).
        pattern = re.compile(".*".join(re.escape(x) for x in want.split("...")))
        found = False
        for s in ("out", "err"):
            k = next((k for k in range(at[s], len(streams[s])) if pattern.fullmatch(streams[s][k])), None)
            if k is None:
                continue
            at[s] = k + 1
            found = True
            break
        if not found:
            return line
    return None


def updated(shown, out, err):
    actual = out + err
    if not any(x.strip() == "..." for x in shown):
        return actual
    keys = {x.split()[0] for x in shown if x.strip() not in ("...", "")}
    result = []
    skipped = False
    for line in actual:
        words = line.split()
        if words and words[0] in keys:
            if skipped and (not result or result[-1].strip() != "..."):
                result.append(re.match(r"^\s*", line).group(0) + "...")
            result.append(line)
            skipped = False
        else:
            skipped = True
    if skipped:
        result.append("...")
    return result


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--massid", required=True)
    ap.add_argument("--update", action="store_true")
    ap.add_argument("files", nargs="+")
    a = ap.parse_args()
    massid = os.path.abspath(a.massid)
    failures = 0
    for path in a.files:
        text = open(path).read()
        lines, found = blocks(text)
        if not found:
            print(f"{path}: no <!-- run --> block", file=sys.stderr)
            failures += 1
            continue
        work = tempfile.mkdtemp(prefix="massid-docs-")
        bindir = os.path.join(work, ".bin")
        os.mkdir(bindir)
        os.symlink(massid, os.path.join(bindir, "massid"))
        for d in ("examples", "tests"):
            os.symlink(os.path.join(ROOT, d), os.path.join(work, d))
        env = dict(os.environ)
        env["PATH"] = bindir + ":/usr/bin:" + env.get("PATH", "")
        env["LC_ALL"] = "C"
        replace = []  # (first line, end line, new lines)
        for start, end, kind in found:
            body = lines[start:end]
            if kind == "sh":
                out, err, rc = run("set -e\n" + "\n".join(body), work, env)
                if rc != 0:
                    print(f"{path}:{start + 1}: the sh block exits {rc}: {' '.join(err[-3:])}")
                    failures += 1
                continue
            for cmd, shown, first in commands(body):
                out, err, rc = run(cmd, work, env)
                missing = check(shown, out, err)
                if missing is not None:
                    if a.update:
                        new = updated(shown, out, err)
                        replace.append((start + first, start + first + len(shown), new))
                    else:
                        print(f"{path}:{start + first + 1}: `{cmd[:70]}` does not print\n    {missing.strip()}\n"
                              f"  it printed (exit {rc}):\n" + "\n".join("    " + x for x in out + err))
                        failures += 1
        if replace:
            for b, e, new in sorted(replace, reverse=True):
                lines[b:e] = new
            tmp = path + ".tmp"
            with open(tmp, "w") as f:
                f.write("\n".join(lines))
            os.replace(tmp, path)
            print(f"{path}: {len(replace)} command outputs rewritten")
        shutil.rmtree(work)
    if failures:
        print(f"{failures} worked example(s) disagree with the program", file=sys.stderr)
        return 1
    print(f"the worked examples of {len(a.files)} file(s) print what the program prints")
    return 0


if __name__ == "__main__":
    sys.exit(main())
