# SPDX-License-Identifier: Apache-2.0
"""Seeded random packet stress of brainstem_dio against the model, with random gaps and
random m_axis_tready, and AXI-Stream rules checked every clock.
"""

from __future__ import annotations

import os
import random

import cocotb
import pytest

from bsd_model import (
    CMD_DEBUG,
    CMD_DIG_CFG,
    CMD_DIG_IO,
    CMD_DIG_RST,
    CMD_HB,
    CMD_PTIME_RD,
    DIGCFG_IODIR,
    MAX_DATA,
    RESYNC_ADDR,
    TIMER_TIMEOUT_S,
    Model,
    Output,
    packet,
)
from bsd_tb import TB, TBError, _hex
import runner
from runner import test_args
from top_builds import BUILDS
from top_helpers import FLAGS, OUT_OF_RANGE, A, P


# Packets per run: the full 10 000 on the GP 1.0 build on both simulators, a smaller share
# on the others. $BSD_STRESS_PACKETS overrides it (e.g. 100000 for a long soak).
STRESS_PACKETS = {
    ("verilator", "gp1"): 10_000,
    ("icarus", "gp1"): 10_000,
    ("verilator", "slow_fixed"): 3_000,
    ("icarus", "slow_fixed"): 2_000,
    ("verilator", "gp2"): 5_000,
    ("icarus", "gp2"): 3_000,
    ("verilator", "high_ids"): 2_000,
    ("icarus", "high_ids"): 1_000,
}


def stress_args(sim: str, build: str) -> dict[str, int]:
    return {"packets": int(os.environ.get("BSD_STRESS_PACKETS", STRESS_PACKETS[(sim, build)]))}


def random_packet(rng: random.Random, m: Model) -> bytes:
    """One random host packet: mostly well-formed commands to us, plus every kind of
    invalid, foreign, probe, N = 0 and N > 8 packet."""
    n_pins = P.num_pins

    def pin_byte() -> int:
        if rng.random() < 0.8:
            return rng.randrange(n_pins)
        return rng.choice(OUT_OF_RANGE + [rng.randrange(256)])

    def devcode() -> int:
        return rng.choice(FLAGS) | (pin_byte() & 0x3F)

    r = rng.random()
    if r < 0.62:
        cmd = rng.choice([CMD_DIG_CFG] * 4 + [CMD_DIG_IO] * 4 + [CMD_DIG_RST, CMD_PTIME_RD, CMD_PTIME_RD,
                                                                 CMD_HB, CMD_DEBUG, rng.randrange(256)])
        if cmd == CMD_DIG_CFG:
            if rng.random() < 0.5:
                data = [cmd, pin_byte()]
            else:
                cfg = rng.randrange(256)
                if rng.random() < 0.6:
                    cfg |= DIGCFG_IODIR  # keep plenty of inputs to read and time
                data = [cmd, pin_byte(), cfg]
        elif cmd == CMD_DIG_IO:
            data = [cmd, devcode()] if rng.random() < 0.6 else [cmd, pin_byte(), rng.choice([0, 1, 0xFF])]
        elif cmd in (CMD_DIG_RST, CMD_PTIME_RD):
            data = [cmd, devcode() if cmd == CMD_PTIME_RD else pin_byte()]
        elif cmd == CMD_DEBUG:
            data = [cmd] + [rng.randrange(256) for _ in range(rng.randint(0, MAX_DATA - 1))]
        else:
            data = [cmd] + [rng.randrange(256) for _ in range(rng.randint(0, 3))]
        u = rng.random()
        if u < 0.08:
            data = data[:1]
        elif u < 0.16:
            data += [rng.randrange(256) for _ in range(rng.randint(1, MAX_DATA - len(data)))] if len(data) < MAX_DATA else []
        return packet(A, *data)
    if r < 0.74:
        addr = rng.choice([a for a in (rng.randrange(256), (A + 1) & 0xFF, (A + 2) & 0xFF, 0) if a not in (A, RESYNC_ADDR)] or [0])
        n = rng.randint(0, MAX_DATA)
        pool = [A, 0, 2, RESYNC_ADDR, CMD_DIG_CFG, CMD_DIG_IO, 9]
        return bytes([addr, n] + [rng.choice(pool) if rng.random() < 0.5 else rng.randrange(256) for _ in range(n)])
    if r < 0.79:
        return packet(RESYNC_ADDR)
    if r < 0.82:
        n = rng.randint(1, MAX_DATA)
        return bytes([RESYNC_ADDR, n] + [rng.choice([A, 0, 2, 26]) for _ in range(n)])
    if r < 0.88:
        return bytes([rng.choice([A, A, RESYNC_ADDR, rng.randrange(256)]), rng.randint(MAX_DATA + 1, 255)])
    if r < 0.91:
        return packet(A)
    if r < 0.94:
        # Raw garbage: the framing may land anywhere; the model follows it byte by byte.
        return bytes(rng.randrange(256) for _ in range(rng.randint(1, 4)))
    n = rng.randint(1, MAX_DATA)
    return bytes([A, n] + [rng.randrange(256) for _ in range(n)])


async def stress_chunk(tb: TB, count: int, rng: random.Random, chunk: int) -> None:
    pins = rng.getrandbits(P.num_pins)
    m = Model(P, pins)
    await tb.start(m, pins)
    tb.source.gap_prob = rng.choice([0.0, 0.2, 0.5])
    tb.sink.ready_prob = rng.choice([1.0, 0.7, 0.3])
    sent: list[bytes] = []
    exp = Output()
    origin: list[int] = []  # which sent packet produced each expected packet
    rflx_origin: list[int] = []
    for i in range(count):
        pk = random_packet(rng, m)
        sent.append(pk)
        out = m.feed(pk)
        exp.extend(out)
        origin += [i] * len(out.packets)
        rflx_origin += [i] * len(out.rflx)
    t_start = tb.now_s()
    for pk in sent:
        tb.source.send_nowait(pk)
    await tb.source.wait_idle()
    await tb.sink.wait_count(tb._n_pkt + len(exp.packets), 50e-3)
    await tb.cycles(100)
    elapsed = tb.now_s() - t_start
    # Timers started here never finish (static pads) unless the chunk outlived a timeout.
    assert elapsed < 0.9 * TIMER_TIMEOUT_S, f"stress chunk took {elapsed * 1e3:.1f} ms: too long for the model"
    tb.check_no_errors()
    got = [p.data for p in tb.new_packets()]
    if got != exp.packets:
        k = next((i for i, (a, b) in enumerate(zip(got, exp.packets)) if a != b), min(len(got), len(exp.packets)))
        src = origin[k] if k < len(origin) else (origin[-1] if origin else 0)
        ctx = "; ".join(_hex(s) for s in sent[max(0, src - 4):src + 1])
        raise TBError(
            f"stress seed {tb.seed} chunk {chunk}: packet #{k} differs: expected "
            f"{_hex(exp.packets[k]) if k < len(exp.packets) else '(none)'} got "
            f"{_hex(got[k]) if k < len(got) else '(none)'}; counts {len(exp.packets)}/{len(got)}; "
            f"host packets up to the one responsible: {ctx}"
        )
    rflx = [(i, d) for _, i, d in tb.new_rflx()]
    if rflx != exp.rflx:
        k = next((i for i, (a, b) in enumerate(zip(rflx, exp.rflx)) if a != b), min(len(rflx), len(exp.rflx)))
        src = rflx_origin[min(k, len(rflx_origin) - 1)] if rflx_origin else 0
        raise TBError(f"stress seed {tb.seed} chunk {chunk}: RFLX #{k} differs near host packet "
                      f"{_hex(sent[src])}: expected {exp.rflx[k:k + 3]} got {rflx[k:k + 3]}")
    if tb.new_trans():
        raise TBError("raw_trans fired with static pads")
    tb.check_pins(m)
    tb.check_no_errors()
    tb.log.info("stress chunk %d: %d packets, %d replies, %d strobes, %.2f ms", chunk, count,
                len(got), len(rflx), elapsed * 1e3)


@cocotb.test()
async def test_stress(dut) -> None:
    """Seeded random packets (valid, invalid, foreign, garbage lengths, N > 8, probes) with
    random m_axis_tready and random s_axis_tvalid gaps, static pads, checked byte for byte
    against the model. Replay with BSD_SEED=<seed in the log> (or the run's COCOTB_RANDOM_SEED)."""
    total = int(test_args()["packets"])
    tb = TB(dut, P)
    tb.log.info("stress: %d packets, seed %d (replay: BSD_SEED=%d), params %s", total, tb.seed, tb.seed,
                P.to_json())
    rng = random.Random(tb.seed)
    chunk, done = 0, 0
    while done < total:
        n = min(1000, total - done)
        await stress_chunk(tb, n, rng, chunk)
        done += n
        chunk += 1


@pytest.mark.parametrize("sim, build", runner.cases(["gp1", "slow_fixed", "gp2", "high_ids"], quick="verilator"))
def test_stress_top(sim: str, build: str) -> None:
    runner.run(sim, "brainstem_dio", __file__, BUILDS[build], build, args=stress_args(sim, build))
