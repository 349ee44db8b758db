#!/usr/bin/env python3
"""The figures of a massid HTML report as PNG files (docs/tracking.md's).

A report embeds each figure as a PNG (data: URI) with an alt text; this
writes those named in FIGURES (alt text -> file name), unchanged, into DIR:

    figures.py tracking.html docs/    # docs/tracking_mass.png, ...

Standard library only.
"""
import base64
import os
import re
import sys

FIGURES = {
    "payload mass along time": "tracking_mass.png",
    "payload centre of mass along time": "tracking_com.png",
    "payload principal moments along time": "tracking_moments.png",
    "offset errors along time": "tracking_offsets.png",
    "compensated wrench along time": "tracking_compensated.png",
}


def main():
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    with open(sys.argv[1], encoding="utf-8") as f:
        html = f.read()
    found = dict((alt, data) for data, alt in
                 re.findall(r'<img src="data:image/png;base64,([^"]+)" alt="([^"]*)">', html))
    missing = [alt for alt in FIGURES if alt not in found]
    if missing:
        print(f"{sys.argv[1]}: no figure {missing[0]!r}", file=sys.stderr)
        return 2
    for alt, name in FIGURES.items():
        path = os.path.join(sys.argv[2], name)
        with open(path, "wb") as f:
            f.write(base64.b64decode(found[alt]))
        print(f"wrote {path}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
