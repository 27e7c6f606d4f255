#!/usr/bin/env python3
# SPDX-License-Identifier: Apache-2.0
"""Static timing estimate of a synth_ice40 netlist (yosys JSON), without placement: for every
flop and block RAM input, its arrival time and LUT levels from flops and RAMs (pads excluded),
so that a change to the RTL is judged on every path at once, not on the one path each
nextpnr seed reports. Delays (ns) are nextpnr-ice40's for the UP5K as its critical-path
reports show them: clock-to-Q 1.39, a LUT 0.87 (I3) to 1.28 (I0), a route 1.76; an enable or
reset input (CEN, SR) is given 3.0 for its route, as it varied from 2.45 to 3.53; a LUT feeds
its flop's D without a route only when it drives nothing else (nextpnr packs it into the
flop's cell). Carry chains and RAM clock-to-out are guesses (0.3 / 0.6, 2.5). On the
iCEBreaker top the worst endpoint read about 0.5 to 2 ns below nextpnr's worst over 5 seeds.

    synth/depth.py [netlist] [--over NS] [--explain REGEX] [--lone]

netlist: synth/build/icebreaker/top.json by default (synth/synth.py --only icebreaker writes
it). Prints the worst arrival, the number of endpoints over NS (default 15.5), and those
endpoints grouped by source and sink register; --explain shows the worst path to the first
endpoint whose cell.port matches REGEX, with each cell's inputs and their arrivals. --lone
counts the flops that nextpnr gives a logic cell of their own (their D is not a LUT that drives
them alone: a flop loaded from a shared net through its enable, or from another flop), by
register: on a full device they, not the LUTs, decide how many logic cells are left (it prints
only that: --over and --explain are for the timing estimate).
"""

from __future__ import annotations

import argparse
import collections
import json
import re
import sys
from pathlib import Path

CLKQ, RAMQ, ROUTE, CEROUTE, SETUP = 1.39, 2.5, 1.76, 3.0, 0.1
LUTD = {"I0": 1.28, "I1": 1.21, "I2": 1.21, "I3": 0.87}
CI_CO, I_CO = 0.3, 0.6
Arrival = tuple[float, int, str, list[str]]   # time, LUT levels, source cell, cells on the path


def short(name: str) -> str:
    """A cell's register name: the top's module path prefix and yosys' suffixes dropped."""
    name = name.replace("u_dio.u_core.", "").replace("u_dio.", "")
    return re.sub(r"_SB_(DFF\w*|LUT4|CARRY|RAM\w*)(_.*)?$", "", name)


class Netlist:
    def __init__(self, path: Path) -> None:
        mods = json.loads(path.read_text())["modules"]
        self.mod = next(m for m in mods.values() if m.get("attributes", {}).get("top"))
        self.cells = self.mod["cells"]
        self.drv: dict[int, str] = {}
        sinks: dict[int, list[tuple[str, str]]] = collections.defaultdict(list)
        for n, c in self.cells.items():
            for p, bits in c["connections"].items():
                for b in bits:
                    if isinstance(b, str):
                        continue
                    if c.get("port_directions", {}).get(p) == "output":
                        self.drv[b] = n
                    else:
                        sinks[b].append((n, p))
        # a LUT packed with its flop: it drives that flop's D alone
        self.packed = set()
        for c in self.cells.values():
            if c["type"] == "SB_LUT4":
                s = sinks.get(c["connections"]["O"][0], [])
                if len(s) == 1 and self.is_ff(s[0][0]) and s[0][1] == "D":
                    self.packed.add(s[0][0])
        self.memo: dict[int, Arrival] = {}

    def is_ff(self, n: str) -> bool:
        return self.cells[n]["type"].startswith("SB_DFF")

    def is_ram(self, n: str) -> bool:
        return self.cells[n]["type"].startswith("SB_RAM")

    def arr(self, b: int | str) -> Arrival:
        """The latest arrival at net bit b; source "" for constants and pads (not timed)."""
        if isinstance(b, str) or b not in self.drv:
            return (0.0, 0, "", [])
        if b in self.memo:
            return self.memo[b]
        n = self.drv[b]
        t = self.cells[n]["type"]
        r: Arrival = (0.0, 0, "", [])
        if self.is_ff(n) or self.is_ram(n):
            r = (CLKQ if self.is_ff(n) else RAMQ, 0, n, [n])
        elif t in ("SB_LUT4", "SB_CARRY"):
            for ip in ("I0", "I1", "I2", "I3") if t == "SB_LUT4" else ("I0", "I1", "CI"):
                ib = self.cells[n]["connections"][ip][0]
                a = self.arr(ib)
                if not a[2]:
                    continue
                if t == "SB_CARRY":
                    v = a[0] + (CI_CO if ip == "CI" else ROUTE + I_CO)
                else:   # I3 from a carry out is a dedicated wire
                    from_carry = not isinstance(ib, str) and self.cells[self.drv[ib]]["type"] == "SB_CARRY"
                    v = a[0] + (0.0 if from_carry else ROUTE) + LUTD[ip]
                if v > r[0]:
                    r = (v, a[1] + (t == "SB_LUT4"), a[2], [*a[3], n])
        self.memo[b] = r
        return r

    def endpoints(self) -> list[tuple[float, int, str, str, Arrival]]:
        eps = []
        for n, c in self.cells.items():
            if not (self.is_ff(n) or self.is_ram(n)):
                continue
            for p, bits in c["connections"].items():
                if c.get("port_directions", {}).get(p) != "input" or p in ("C", "RCLK", "WCLK"):
                    continue
                for b in bits:
                    a = self.arr(b)
                    if not a[2]:
                        continue
                    if p in ("E", "R", "S"):
                        route = CEROUTE
                    elif p == "D" and self.is_ff(n) and a[1] > 0:
                        route = 0.0 if n in self.packed else ROUTE + LUTD["I0"]   # else a pass-through LUT
                    else:
                        route = ROUTE
                    eps.append((a[0] + route + SETUP, a[1], n, p, a))
        return sorted(eps, key=lambda e: -e[0])


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(prog="synth/depth.py", description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("netlist", nargs="?", default=str(Path(__file__).parent / "build/icebreaker/top.json"))
    ap.add_argument("--over", type=float, default=15.5, metavar="NS")
    ap.add_argument("--explain", metavar="REGEX")
    ap.add_argument("--lone", action="store_true")
    args = ap.parse_args(argv)
    try:
        net = Netlist(Path(args.netlist))
    except (OSError, ValueError, KeyError, StopIteration, TypeError, AttributeError) as e:
        ap.error(f"{args.netlist}: not a yosys JSON netlist ({e.__class__.__name__}: {e})")
    if args.lone:
        ffs = [n for n in net.cells if net.is_ff(n)]
        lone = collections.Counter(short(n) for n in ffs if n not in net.packed)
        print(f"{len(ffs)} flops, {sum(lone.values())} in a logic cell of their own:")
        for reg, k in lone.most_common():
            print(f"{k:6d}  {reg}")
        return 0
    sys.setrecursionlimit(100_000)
    eps = net.endpoints()
    over = [e for e in eps if e[0] > args.over]
    luts = sum(c["type"] == "SB_LUT4" for c in net.cells.values())
    print(f"{luts} LUT4, {len(eps)} endpoints; worst {eps[0][0]:.2f} ns ({1000 / eps[0][0]:.1f} MHz); "
          f"over {args.over:g} ns: {len(over)}; at 5 LUT levels or more: {sum(e[1] >= 5 for e in eps)}")
    groups: dict[tuple[str, str, str], list] = collections.defaultdict(list)
    for e in over:
        groups[(short(e[4][2]), short(e[2]), e[3])].append(e)
    for (src, dst, p), es in groups.items():
        print(f"{es[0][0]:6.2f} ns  {es[0][1]} LUTs  x{len(es):<3d} {src} -> {dst}.{p}")
    if args.explain:
        e = next((e for e in eps if re.search(args.explain, f"{e[2]}.{e[3]}")), None)
        if e is None:
            print(f"no endpoint matches {args.explain}")
            return 1
        print(f"--- {e[0]:.2f} ns {e[2]}.{e[3]}")
        names = {b: k for k, v in net.mod["netnames"].items() for b in v["bits"] if not isinstance(b, str)}
        for x in e[4][3]:
            c = net.cells[x]
            ins = [f"{ip}={names.get(b, b)}@{net.arr(b)[0]:.1f}" for ip in ("I0", "I1", "I2", "I3", "CI")
                   if ip in c["connections"] and not isinstance(b := c["connections"][ip][0], str)]
            print(f"  {c['type']:9s} {short(x)[:50]:50s} " + ", ".join(ins))
    return 0


if __name__ == "__main__":
    sys.exit(main())
