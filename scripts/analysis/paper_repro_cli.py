"""Command line of scripts/paper-repro (docs/paper-reproduction.md): the paper's
statements, figure by figure, from the campaign's stored runs, as OUT/paper-repro.md
(figures linked) and OUT/paper-repro.json, and, with --doc, the generated block of
docs/paper-reproduction.md.

Exit status: 0 written (whatever the verdicts: they are in the document); 2 a bad plan,
a stored record that cannot be read, a doc without its block, or an unwritable output.
"""

from __future__ import annotations

import argparse
import os
import sys
from pathlib import Path
from typing import Sequence

from campaign_lib.plan import resolve
from common import templates
from common.fsutil import write_atomic
from common.jsonsafe import dumps
from common.paths import REPO_ROOT

from . import headline, paper_repro

TEMPLATE = "paper_repro.md.j2"
#: The block of the doc that --doc rewrites; the rest of the doc is written by hand.
BEGIN = "<!-- begin: scripts/paper-repro --doc -->"
END = "<!-- end: scripts/paper-repro --doc -->"


def _parse(argv: Sequence[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(
        prog="paper-repro",
        description="The paper's checkable statements (Table 1, Figs. 3a-d, 4a-b, 5, 6, 7a-b, the "
                    "halving at 6 deg) with the paper's words, the checks and their verdict at the "
                    "paper's scale from the campaign's stored runs, the runs behind each verdict, what "
                    "is still to run and the reduced-scale verdicts beside them. Writes "
                    "OUT/paper-repro.md, OUT/paper-repro.json and OUT/figures/.",
        epilog="Exit status: 0 written; 2 bad plan, unreadable stored record, a doc without its "
               "block, or unwritable output.")
    parser.add_argument("--plan", default="paper", metavar="PLAN",
                        help="the campaign plan: a name (validation/campaigns/PLAN.json) or a file "
                             "(default: paper)")
    parser.add_argument("--results", metavar="DIR",
                        help="its stored runs (default: validation/results/<plan name>)")
    parser.add_argument("--records", metavar="DIR", default=str(REPO_ROOT / "validation" / "results"),
                        help="stored headline records of reduced scales, shown beside the verdicts "
                             "(default: validation/results)")
    parser.add_argument("--out", metavar="OUT", default=str(REPO_ROOT / "out" / "paper-repro"),
                        help="folder for paper-repro.md, paper-repro.json, figures/ and the assembled "
                             "sweeps/ (default: out/paper-repro)")
    parser.add_argument("--doc", metavar="FILE",
                        help=f"also rewrite the block between '{BEGIN}' and '{END}' of FILE (e.g. "
                             "docs/paper-reproduction.md); figures are named there, not linked")
    return parser.parse_args(argv)


def replace_block(text: str, block: str, where: str) -> str:
    """The doc with its generated block replaced: the lines between a line that is
    BEGIN and the next line that is END (a marker quoted inside a line is text);
    ValueError naming the file when they are missing."""
    lines = text.splitlines(keepends=True)
    bare = [line.strip() for line in lines]
    try:
        start = bare.index(BEGIN)
        end = bare.index(END, start + 1)
    except ValueError:
        raise ValueError(f"{where}: no block '{BEGIN}' ... '{END}' (each on a line of its own) "
                         "to rewrite") from None
    return "".join(lines[:start + 1]) + block.strip("\n") + "\n" + "".join(lines[end:])


def main(argv: Sequence[str] | None = None) -> int:
    args = _parse(argv)

    def error(message: str) -> int:
        print(f"paper-repro: error: {message}", file=sys.stderr)
        return 2

    plan = resolve(args.plan)
    results = Path(args.results) if args.results else REPO_ROOT / "validation" / "results" / plan.stem
    out = Path(args.out)
    try:
        reduced = [("Stored", r) for r in headline.load_records(Path(args.records))]
        data = paper_repro.build(plan, results, out, reduced)
    except (paper_repro.PaperReproError, headline.RecordError) as problem:
        return error(str(problem))
    except OSError as problem:
        return error(f"cannot write in {out}: {problem}")

    def linked(path: Path) -> dict:
        return {"link": os.path.relpath(path, out).replace(os.sep, "/")}

    try:
        write_atomic(out / "paper-repro.md", "# " + paper_repro.TITLE + "\n" + templates.render(
            TEMPLATE, {"paper": paper_repro.with_figures(data, linked), "paper_missing": ""}))
        write_atomic(out / "paper-repro.json", dumps(data))
        if args.doc:
            doc = Path(args.doc)
            block = templates.render(TEMPLATE, {"paper": paper_repro.with_figures(
                data, lambda path: {"link": None}), "paper_missing": ""})
            write_atomic(doc, replace_block(doc.read_text(encoding="utf-8"), block, str(doc)))
    except ValueError as problem:
        return error(str(problem))
    except OSError as problem:
        return error(f"cannot write the results: {problem}")

    for s in data["statements"]:
        print(f"{s['figure']}: {s['verdict']} [{s['runs']} runs]")
    written = [out / "paper-repro.md", out / "paper-repro.json"] + ([Path(args.doc)] if args.doc else [])
    figures = sum(len(s["figures"]) for s in data["statements"])
    print(f"paper-repro: wrote {', '.join(str(p) for p in written)} and {figures} figure(s)")
    print(f"paper-repro: {data['stored']} of {data['planned']} runs stored; still to run: {data['todo']}")
    return 0
