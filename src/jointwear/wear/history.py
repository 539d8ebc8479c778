"""The long run: wear of the clearance joints over hundreds of thousands of cycles.

Simulating every cycle (the paper's Step 5) costs hours per model call. Instead (the user guide's baseline reading, "Wear"):

1. simulate a few steady cycles on the current geometry (settle, then record `record_cycles` cycles),
2. integrate the Archard wear of the recorded steps on the bearing and journal grids -> wear per cycle,
3. extrapolate that rate over a block of cycles (explicit Euler in cycles), update the geometry, repeat to N.

The block size is fixed (`block_cycles`, default) or adaptive (`block_rule = "adaptive"`: it starts at
`initial_block`, grows by `block_growth` while the bearing's Archard volume rate changes by less than
`rate_tolerance` between blocks, and is halved when it changes by more than twice that). The history (max depth
after every block) is linear between block ends to well under 1 % because the rate is nearly constant (the
paper's Monte Carlo means are linear in cycles), so `max_wear_at(N)` interpolates it.
"""

from __future__ import annotations

import dataclasses
import inspect
import math
import os
import threading
import time
from collections import deque
from concurrent.futures import ThreadPoolExecutor
from typing import Any, Callable, NamedTuple

import numpy as np

from jointwear.contact.envelope import admissible_set, rounded_envelope
from jointwear.contact.geometry import PROFILE_ROUNDING
from jointwear.mechanism.results import whirl_measure

from .cycle import CycleWear, JointMaterials, cycle_wear, mean_half_width
from .kernels import TWO_PI, smooth_periodic
from .results import BlockRecord, JointWear, WearResult, find_peaks_periodic, top_centre
from .settings import WearSettings, check_cycles


def contact_profiles(c0: float, wb: np.ndarray, wj: np.ndarray, settings: WearSettings):
    """Profiles given to the contact search in profile mode and the touching-point maps (None for 'radial', for a
    round side, and for the distributed deposit, which does not use them), from the worn profiles wb, wj as the
    contact sees them (:func:`smoothed_profiles`)."""
    if settings.profile_contact == "radial":
        return wb.copy(), wj.copy(), None, None

    def touch_map(w):
        ce = np.empty_like(w)
        idx = np.empty(w.shape[0], dtype=np.int64)
        admissible_set(c0 + w, ce, idx)
        return np.maximum(ce - c0, 0.0), idx

    def rounded(w):  # the admissible set with its corners rounded (contact.envelope)
        r = np.empty_like(w)
        rounded_envelope(c0 + w, PROFILE_ROUNDING * c0, r)
        return np.maximum(r - c0, 0.0)

    # the bore's corners are rounded so that a journal resting in a pocket worn to its own shape meets a smooth
    # contact normal; with the distributed deposit the journal's too (a pin's flat resting on the bore)
    distributed = settings.profile_deposit == "distributed"
    hb, ib = rounded(wb), None
    if not distributed and wb.any():  # a round side touches where its normal points: no map (the map's identity)
        ib = touch_map(wb)[1]
    hj, ij = wj.copy(), None
    if wj.any():
        hj, ij = (rounded(wj), None) if distributed else touch_map(wj)
    return hb, hj, ib, ij


def smoothed_profiles(wb: np.ndarray, wj: np.ndarray, settings: WearSettings):
    """The worn profiles as the contact sees them: smoothed over the running-in length, never negative."""
    if settings.profile_smoothing_deg > 0.0:
        wb = np.maximum(smooth_periodic(wb, settings.profile_smoothing_deg), 0.0)
        wj = np.maximum(smooth_periodic(wj, settings.profile_smoothing_deg), 0.0)
    return wb, wj


class WornGeometry(NamedTuple):
    """A joint's geometry for one block and what its wear needs (wear.cycle.cycle_wear)."""

    geometry: Any  # ClearanceGeometry for the dynamics
    bearing_touch: np.ndarray | None = None  # profile mode, 'touch' deposit: the touching points' maps
    journal_touch: np.ndarray | None = None
    bearing_bore: np.ndarray | None = None  # profile mode, distributed deposit: the contact profiles the load shares
    journal_surface: np.ndarray | None = None


def update_geometry(g0, settings: WearSettings, wb: np.ndarray, wj: np.ndarray, growth: float) -> WornGeometry:
    """The unworn ClearanceGeometry ``g0`` worn by the profiles wb, wj (profile mode) or the clearance growth
    (uniform mode)."""
    if settings.geometry_mode == "profile":
        c0 = float(g0.bearing_radius - g0.journal_radius + g0.clearance_growth)
        seen_b, seen_j = smoothed_profiles(wb, wj, settings)
        hb, hj, ib, ij = contact_profiles(c0, seen_b, seen_j, settings)
        bore = pin = None
        if settings.profile_deposit == "distributed":  # the load is shared over the profiles the contact sees
            bore, pin = seen_b, (seen_j if settings.track_journal else None)
        return WornGeometry(dataclasses.replace(g0, use_profile=True, bearing_wear=hb, journal_wear=hj), ib, ij,
                            bore, pin)
    return WornGeometry(dataclasses.replace(g0, use_profile=False, clearance_growth=float(growth)))


#: The shares of the load level a bore cell that stands out by eps at a rate g eps (CycleWear.levelling_rate); an
#: explicit update over dn cycles overshoots that when g dn is large, and a ripple of some degrees grows from block to
#: block. A block's wear is therefore laid in sub-steps that re-share the same recorded loads over the bore as it
#: wears (the dynamics changes slowly and is not re-run): of LEVELLING_STEP / g cycles, up to MAX_LEVELLING_SUBSTEPS
#: of them (this resolves a steady conformal load, the rig of docs/verification.md), and never longer than
#: WearSettings.profile_substep_cycles (a rotating load levels faster than any affordable step; there the running-in
#: smoothing keeps the sub-steps smooth and their length sets the accuracy).
LEVELLING_STEP = 2.0
MAX_LEVELLING_SUBSTEPS = 16
#: The sub-steps after the first share the block's loads gathered into direction cells this many grid cells wide
#: (ConformalShare.merged): the increments are smoothed over the running-in length (3 deg) anyway; on the wing it
#: moves the max depth by < 0.5 % and makes a sub-step 3-4x cheaper.
SUBSTEP_MERGE = 4


def lay_distributed(share, rate: np.ndarray, volume: float, levelling_rate: float, w: np.ndarray, dn: int,
                    settings: WearSettings):
    """Profile mode, distributed deposit: lay a block's wear on one side's profile w in sub-steps (see
    LEVELLING_STEP), the first at the block's own rate and volume per cycle, the others re-sharing the block's loads
    (ConformalShare `share`) over the profile as it wears; each increment smoothed over the running-in length as
    the contact sees the profile (a ripple shorter than it is invisible to the shares and would otherwise grow from
    their grid-scale noise; the profile is the sum of the increments, so this smooths it once, not once per block,
    and conserves the worn area). Returns (new profile, Archard volume of the block)."""
    m = max(1, min(MAX_LEVELLING_SUBSTEPS, math.ceil(levelling_rate * dn / LEVELLING_STEP)),
            math.ceil(dn / settings.profile_substep_cycles))
    if settings.profile_smoothing_deg > 0.0:
        rate = np.maximum(smooth_periodic(rate, settings.profile_smoothing_deg), 0.0)
    w = w + rate * (dn / m)
    vol = volume * (dn / m)
    if m > 1:
        merged = share.merged(SUBSTEP_MERGE) if SUBSTEP_MERGE > 1 else share
        vol += merged.lay(w, m - 1, dn / m, settings.profile_smoothing_deg)
    return w, vol


def growth_depth(settings: WearSettings, wb: np.ndarray, wj: np.ndarray) -> float:
    """Uniform mode: the wear depth by which the clearance grows (WearSettings.uniform_growth)."""
    if settings.uniform_growth == "bearing_max":
        return float(wb.max())
    return float(wb.max() + wj.max())


def lane_threads(lanes: int, threads: int | None = None) -> int:
    """Threads that run the lanes: min(lanes, threads), threads defaulting to the cores this process may use. The
    result never depends on it (see WearSettings.lanes)."""
    if threads is None:
        threads = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else (os.cpu_count() or 1)
    return max(1, min(lanes, int(threads)))


def used_up(g0, settings: WearSettings, wj: np.ndarray, growth: float) -> str | None:
    """Why joint geometry ``g0`` worn by the journal profile wj (and, in uniform mode, the clearance growth) can no
    longer be run, or None: the journal worn to its radius (the pin is gone), or in uniform mode a growth that leaves
    the journal no radius (R_j - growth / 2 <= 0, paper Eq. 37)."""
    r_j = float(g0.journal_radius)
    depth = float(wj.max())
    if depth >= r_j:
        return f"the journal is worn {depth * 1e3:.3g} mm deep, as deep as its radius ({r_j * 1e3:.3g} mm)"
    if settings.geometry_mode == "uniform" and growth >= 2.0 * r_j:  # the dynamics' journal radius R_j - growth / 2
        return (f"the clearance has grown {growth * 1e3:.3g} mm, more than the journal's diameter "
                f"({2e3 * r_j:.3g} mm): uniform mode leaves the journal no radius")
    return None


def wear_history(
    model,
    settings: WearSettings,
    n_cycles=None,
    *,
    settle_cycles: float | None = None,
    threads: int | None = None,
    simulate: Callable | None = None,
    geometry: list | None = None,
    progress: Callable[[int, int], Any] | None = None,
) -> WearResult:
    """Run the wear history of every clearance joint of `model` to `n_cycles` crank cycles.

    Parameters
    ----------
    model : MechanismModel
        The mechanism (jointwear.mechanism.build_model).
    settings : WearSettings
        The wear settings (``config.wear``).
    n_cycles : int, optional
        Cycles to run (default settings.cycles); validated (finite, > 0, whole).
    settle_cycles : float, optional
        Cycles the first block of a lane settles from rest when ``settings.settle_cycles_initial`` is not set
        (lane j settles j / lanes cycle longer); default the mechanism's ``model.settings.settle_cycles``
        (``config.simulation.settle_cycles``).
    threads : int, optional
        Most threads that run the lanes (default: the cores this process may use; a study's local worker
        processes pass the same). The result does not depend on it.
    simulate : callable, optional
        The dynamics entry point (default `jointwear.mechanism.simulate`); injectable for tests.
    geometry : list of ClearanceGeometry, optional
        Initial geometry (default `model.initial_geometry()`).
    progress : callable, optional
        Called as ``progress(done, n_cycles)`` after every block.

    A history whose joint is worn away (:func:`used_up`) stops at the end of that block: the result's
    ``stopped_at`` and ``stop_reason`` say when and why, and its histories end there (a reliability model call
    reports a wear no allowance reaches past that point: study.model_call.WORN_AWAY_WEAR).
    """
    t_wall = time.perf_counter()
    if n_cycles is None:
        n_cycles = settings.cycles
        if n_cycles is None:
            raise ValueError("cycles must be given (argument or wear.cycles)")
    n_cycles = check_cycles(n_cycles, "cycles")
    if simulate is None:
        from jointwear.mechanism import simulate as simulate  # noqa: PLW0127
    # set when the history stops: a look-ahead block still in flight is not needed (a simulate that takes it)
    cancel = threading.Event() if "cancel" in inspect.signature(simulate).parameters else None
    geoms0 = list(geometry) if geometry is not None else list(model.initial_geometry())
    nj = len(geoms0)
    if nj == 0:
        raise ValueError("the model has no clearance joint: nothing wears")
    n = settings.n_grid
    theta = TWO_PI * np.arange(n) / n
    wb = [np.zeros(n) for _ in range(nj)]
    wj = [np.zeros(n) for _ in range(nj)]
    growth = [float(g.clearance_growth) for g in geoms0]
    growth0 = list(growth)
    vol_b = [0.0] * nj
    vol_j = [0.0] * nj
    laid = [np.zeros(n) for _ in range(nj)]  # the last block's growth of each bearing cell, m per cycle
    hist_c = [0]
    hist_b = [[0.0] for _ in range(nj)]
    hist_j = [[0.0] for _ in range(nj)]
    hist_g = [[g] for g in growth]
    mats: list[JointMaterials | None] = [None] * nj
    first: list[CycleWear | None] = [None] * nj
    last: list[CycleWear | None] = [None] * nj
    blocks: list[BlockRecord] = []
    done = 0
    block = settings.initial_block if settings.block_rule == "adaptive" else settings.block_cycles
    prev_vrate = None
    sim_seconds = 0.0
    sim_cycles = 0.0
    n_steps = 0
    rec = settings.record_cycles
    # lanes: independent dynamics chains simulating alternate blocks (see WearSettings.lanes). Block k continues
    # from the end state of block k - lanes and sees the wear of blocks 0 .. k - lanes; the schedule, hence the
    # result, does not depend on how many threads run it.
    lanes = settings.lanes if settings.block_rule == "fixed" else 1
    n_blocks = math.ceil(n_cycles / block) if settings.block_rule == "fixed" else None
    lane_state: list = [None] * lanes
    settle0 = settings.settle_cycles_initial
    if settle0 is None:
        settle0 = model.settings.settle_cycles if settle_cycles is None else settle_cycles
    inflight: deque = deque()
    k_next = 0
    stopped_at, stop_reason = None, None

    def run_block(geoms, state, settle):
        t0 = time.perf_counter()
        res = simulate(model, rec, geometry=geoms, settle_cycles=settle, state0=state,
                       rtol=settings.rtol, atol=settings.atol, **({"cancel": cancel} if cancel is not None else {}))
        return res, time.perf_counter() - t0

    threads = lane_threads(lanes, threads)
    pool = ThreadPoolExecutor(threads, thread_name_prefix="jointwear-lane") if threads > 1 else None
    try:
        while done < n_cycles:
            while len(inflight) < lanes and (k_next < n_blocks if n_blocks is not None else not inflight):
                lane = k_next % lanes
                upd = [update_geometry(geoms0[i], settings, wb[i], wj[i], growth[i]) for i in range(nj)]
                geoms = [u.geometry for u in upd]
                state = lane_state[lane]
                if state is not None:
                    settle = settings.settle_cycles
                else:  # first block of a lane: from rest; lane j settles j / lanes cycle longer (another phase)
                    settle = settle0 + lane / lanes if lane > 0 else settle0
                job = (geoms, state, settle)
                fut = pool.submit(run_block, *job) if pool is not None else job  # serial: run when its turn comes
                inflight.append((lane, upd, geoms, list(growth), settle, fut))
                k_next += 1
            lane, upd, geoms, growth_used, settle, fut = inflight.popleft()
            res, dt_sim = fut.result() if pool is not None else run_block(*fut)
            sim_seconds += dt_sim
            sim_cycles += float(res.n_cycles) + float(res.settle_cycles)
            n_steps += int(res.n_steps)
            lane_state[lane] = res.state_end
            rates = []
            for i, tr in enumerate(res.joints):
                if mats[i] is None:
                    mats[i] = JointMaterials.from_trace(tr, geoms0[i])
                prof = settings.geometry_mode == "profile"
                cw = cycle_wear(tr, settings, rec, mats[i], growth=growth_used[i],
                                bearing_profile=geoms[i].bearing_wear if prof else None,
                                journal_profile=geoms[i].journal_wear if prof else None,
                                bearing_touch=upd[i].bearing_touch, journal_touch=upd[i].journal_touch,
                                bearing_bore=upd[i].bearing_bore, journal_surface=upd[i].journal_surface)
                if first[i] is None:
                    first[i] = cw
                last[i] = cw
                rates.append(cw)
            peak = float(rates[0].bearing.max())
            vrate = rates[0].volume_bearing
            change = float("nan")
            if prev_vrate is not None:
                change = abs(vrate - prev_vrate) / max(prev_vrate, 1e-300)
                if settings.block_rule == "adaptive":
                    if change > 2.0 * settings.rate_tolerance:
                        block = max(settings.min_block, block // 2)
                    elif change < settings.rate_tolerance:
                        block = min(settings.max_block, int(round(block * settings.block_growth)))
            prev_vrate = vrate
            dn = min(block, n_cycles - done)
            for i, cw in enumerate(rates):
                before = wb[i].copy()
                if cw.share is not None:
                    wb[i], vb_add = lay_distributed(cw.share, cw.bearing, cw.volume_bearing, cw.levelling_rate,
                                                    wb[i], dn, settings)
                else:
                    wb[i] += cw.bearing * dn
                    vb_add = cw.volume_bearing * dn
                if cw.journal_share is not None:
                    wj[i], vj_add = lay_distributed(cw.journal_share, cw.journal, cw.volume_journal,
                                                    cw.journal_levelling_rate, wj[i], dn, settings)
                else:
                    wj[i] += cw.journal * dn
                    vj_add = cw.volume_journal * dn
                laid[i] = (wb[i] - before) / dn
                vol_b[i] += vb_add
                vol_j[i] += vj_add
                if settings.geometry_mode == "uniform":
                    growth[i] = growth0[i] + growth_depth(settings, wb[i], wj[i])
                hist_b[i].append(float(wb[i].max()))
                hist_j[i].append(float(wj[i].max()))
                hist_g[i].append(growth[i])
            spin = [whirl_measure(tr, res.n_cycles) for tr in res.joints]
            blocks.append(BlockRecord(done, dn, peak, change, dt_sim, int(res.n_steps),
                                      tuple(n for n, _ in spin), tuple(w for _, w in spin)))
            done += dn
            hist_c.append(done)
            if progress is not None:
                progress(done, n_cycles)
            del res, fut  # the block's record, before the next block is waited for
            gone = [(i, why) for i in range(nj) if (why := used_up(geoms0[i], settings, wj[i], growth[i]))]
            if gone and done < n_cycles:
                stopped_at, stop_reason = done, f"joint {model.clearance_joints[gone[0][0]].name}: {gone[0][1]}"
                break
    finally:
        if cancel is not None:
            cancel.set()
        if pool is not None:
            for item in inflight:
                item[-1].cancel()
            pool.shutdown(wait=True)

    joints = []
    for i in range(nj):
        mo = first[i].mean_orientation
        jw = JointWear(
            index=i, theta=theta, bearing_wear=wb[i], journal_wear=wj[i], mean_orientation=mo,
            history_cycles=np.asarray(hist_c, dtype=float), history_max_bearing=np.asarray(hist_b[i]),
            history_max_journal=np.asarray(hist_j[i]), history_clearance_growth=np.asarray(hist_g[i]),
            volume_bearing=vol_b[i], volume_journal=vol_j[i], bearing_radius=mats[i].r_b0,
            journal_radius=mats[i].r_j0, width=mats[i].width, peaks=[], diagnostics=last[i], first_rate=first[i],
            last_growth=laid[i],
            contact_half_width=mean_half_width(first[i], mats[i], settings),
        )
        jw.peaks = [{"angle_deg": jw.grid_angle_deg(top_centre(wb[i], k)), "depth": float(wb[i][k])}
                    for k in find_peaks_periodic(wb[i], settings.peak_prominence, settings.peak_separation_deg)]
        joints.append(jw)
    return WearResult(joints, settings, n_cycles, blocks, time.perf_counter() - t_wall, sim_seconds, sim_cycles,
                      n_steps, stopped_at, stop_reason)
