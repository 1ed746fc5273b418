#!/usr/bin/env python3
"""Pre-renders the formulas of the core crate's rustdoc as MathML.

A formula is written in LaTeX in a doc comment, as an HTML comment on a line of its own,

    /// <!-- tex: V_k = -\\sigma \\Delta_\\sigma Q_k -->

and the line after it is the rendered MathML, which this script writes (or rewrites):

    /// <math display="block">…</math>

Browsers render MathML natively, so the docs show the formulas with no script, no font
download and no network, under `cargo doc` and on docs.rs alike. Run after editing a formula:

    pip install latex2mathml && python3 core/docs/math/render.py

`tests/tests/project/module_graph.rs` checks that every formula has its rendered line.
"""
import pathlib
import re
import sys

from latex2mathml.converter import convert

ROOT = pathlib.Path(__file__).resolve().parents[3]
TEX = re.compile(r"^(\s*)(///|//!) <!-- tex: (.*) -->$")


def render(path: pathlib.Path) -> bool:
    lines = path.read_text().split("\n")
    out, changed, i = [], False, 0
    while i < len(lines):
        line = lines[i]
        out.append(line)
        match = TEX.match(line)
        i += 1
        if not match:
            continue
        indent, marker, tex = match.groups()
        math = convert(tex, display="block").replace(
            ' xmlns="http://www.w3.org/1998/Math/MathML"', ""
        )
        rendered = f"{indent}{marker} {math}"
        if i < len(lines) and "<math" in lines[i]:
            changed |= lines[i] != rendered
            i += 1
        else:
            changed = True
        out.append(rendered)
    if changed:
        path.write_text("\n".join(out))
    return changed


def main() -> int:
    for path in sorted((ROOT / "core" / "src").rglob("*.rs")):
        if render(path):
            print(f"rendered {path.relative_to(ROOT)}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
