"""The whole config checked before any stage runs: every cross-section rule, every problem listed.

The schema (pydantic) has already checked each section on loading; this adds the rules that join sections
(the R(N) curve and the stages that read it, the limit state's joints and allowances, the random inputs a
reliability stage needs, the compute settings), the assembly of a general linkage over its cycle, and the one
check that needs the model: the nominal mechanism runs.
"""

from __future__ import annotations

import math
import os
from pathlib import Path
from typing import Any
from urllib.parse import urlsplit

from jointwear.config import StudyConfig, target_display_unit
from jointwear.contact.settings import FrictionConfig
from jointwear.schema import ConfigError, item_key
from jointwear.study.limit_state import (
    allowance_stock_problems,
    archard_trend_applies,
    limit_state_from_config,
    limit_state_problems,
    wearable_stock,
)
from jointwear.study_settings import MAX_MC_SAMPLES
from jointwear.units import suffix_unit

RELIABILITY_STAGES = frozenset({"reliability", "sensitivity"})
SCHEDULER_SCHEMES = ("tcp", "tls", "inproc", "ws", "wss", "ucx")


def shown(value: float, target: str) -> str:
    """A random variable's SI number as the user reads it, with its unit: '350 HB', '7.62 mm', '110 GPa'."""
    from jointwear.config import display_unit
    from jointwear.units import to_display

    number, unit = to_display(value, display_unit(target))
    return f"{number:.6g} {unit}" if unit else f"{number:.6g}"


def scheduler_problem(address: str | None) -> str | None:
    """Why a Dask scheduler address cannot be used (None when it parses: scheme://host:port, or host:port for tcp)."""
    if address is None:
        return None
    from jointwear.compute.executors import scheduler_url

    parts = urlsplit(scheduler_url(address))
    if parts.scheme not in SCHEDULER_SCHEMES:
        return (f"compute.scheduler: '{address}' is not a Dask scheduler address "
                f"(expected e.g. tcp://host:8786 or host:8786; schemes {', '.join(SCHEDULER_SCHEMES)})")
    try:
        port = parts.port
    except ValueError:
        port = None
    if parts.scheme != "inproc" and (not parts.hostname or port is None):
        return f"compute.scheduler: '{address}' needs a host and a port (e.g. tcp://host:8786)"
    return None


#: seconds to wait for a Dask scheduler's port, then for its answer, before calling it unreachable (distributed itself
#: waits 30 s for the port, and for ever for the answer of a port that accepts and says nothing)
SCHEDULER_CONNECT_SECONDS = 5.0


def scheduler_unreachable(address) -> str | None:
    """Why nothing answers as a Dask scheduler at an address (a tcp:// or tls:// host whose port refuses, does not
    answer within ``SCHEDULER_CONNECT_SECONDS``, or is another service's); None when a scheduler answers, or for
    anything that is not such an address (a Client or cluster object, inproc://)."""
    if not isinstance(address, str) or scheduler_problem(address) is not None:
        return None
    from jointwear.compute.executors import scheduler_not_answering, scheduler_url

    address = scheduler_url(address)
    parts = urlsplit(address)
    if parts.scheme not in ("tcp", "tls"):
        return None
    import socket

    try:  # a refused port is told at once (distributed retries it until its time-out)
        socket.create_connection((parts.hostname, parts.port), timeout=SCHEDULER_CONNECT_SECONDS).close()
    except OSError as exc:
        return (f"cannot reach the Dask scheduler at '{address}' ({exc.strerror or exc}); start it with `dask "
                "scheduler` and give its tcp:// address")
    try:
        import distributed  # noqa: F401 - without it the executor says how to install it
    except ImportError:
        return None
    return scheduler_not_answering(address, SCHEDULER_CONNECT_SECONDS)


def nominal_wear_cycles(config: StudyConfig) -> int | None:
    """Cycles of the nominal wear history: ``wear.cycles``, else the end of the R(N) curve, else None."""
    if config.wear.cycles is not None:
        return config.wear.cycles
    return config.reliability.cycles_stop


def config_problems(config: StudyConfig, stages: frozenset[str] | set[str]) -> list[str]:
    """Every cross-section problem of ``config`` for running ``stages`` (empty when it can run). The design stage's
    own problems are the design package's ``design_problems``, which the study facade adds."""
    problems: list[str] = []
    needs_reliability = bool(set(stages) & RELIABILITY_STAGES)
    if needs_reliability:
        if config.uncertainty is None or not config.uncertainty.all_specs():
            problems.append("uncertainty: the reliability stages need random variables (an [uncertainty] section "
                            "with [[uncertainty.variables]] or [uncertainty.clearance])")
        curve = config.reliability.curve_problems()
        problems += curve
        problems += limit_state_problems(config)
        if "sensitivity" in stages and not curve:
            grid = config.reliability.curve_cycles()
            c = config.sensitivity.cycles
            if c is not None and c not in grid:
                problems.append(f"sensitivity.cycles: {c} is not one of the R(N) curve's cycle counts {grid}")
    elif "wear" in stages and not config.clearance_joints:
        problems.append("clearance_joints: the wear stage needs at least one clearance joint")
    elif "wear" in stages:
        problems += allowance_stock_problems(config)
    problem = scheduler_problem(config.compute.scheduler)
    if problem:
        problems.append(problem)
    from jointwear.mechanism import (
        check_assembly,  # the numerical check that follows the schema
    )

    try:
        check_assembly(config)
    except ConfigError as exc:
        problems += exc.problems
    return problems


#: a random variable's mean this many standard deviations from the drawn value is worth a warning: beyond rounding
#: (the presets' one shift, the paper's E_j given to three figures, is 0.05 sigma), and well below a change of the
#: drawn value alone, which R(N) does not follow (a 20 % change of a nominal wear coefficient is 2 sigma).
MEAN_SHIFT_WARNING_SIGMAS = 0.1


#: a design specification this many times larger or smaller than its variable's mean is worth a warning
DESIGN_SCALE_WARNING = 100.0

#: an allowance this many times the joint's clearance, on a joint whose bearing wall is not given to check it
#: against, is worth a warning (the presets' largest is 15, on a joint whose wall is given: jin2025_flapping_wing)
ALLOWANCE_CLEARANCE_WARNING = 5.0

#: a truncation at the minimum clearance that moves the sampled clearance's mean by this share is worth a warning
TRUNCATED_MEAN_SHIFT_WARNING = 0.1


def population_reach(n_mc: int) -> float:
    """How many standard deviations from its mean a normal population of ``n_mc`` samples reaches: the quantile
    that one sample in n_mc exceeds on either side (4.6 for 238,691). A design specification whose mean lies beyond
    it is outside what the study's surrogate has seen."""
    from scipy.stats import norm

    return float(norm.isf(0.5 / max(int(n_mc), 1)))


def _fit_mean(option, clearance) -> float | None:
    """The mean clearance a design's fit option gives the study's clearance: its letters' (the middle of the ISO
    limits at the clearance's size), its own, or None (the study's mean kept; or letters the checks refuse)."""
    if option.fit is None:
        return option.mean
    try:
        return option.applied_to(clearance).mean
    except ValueError:  # pydantic's ValidationError too: design.checks names the problem
        return None


def design_warnings(config: StudyConfig) -> list[str]:
    """Design specifications whose mean is more than ``DESIGN_SCALE_WARNING`` times larger or smaller than the
    study's mean of their variable (a fit's mean against the clearance's): the sign of a unit slip, such as
    ``mean = 120`` meant in HB (read as 120 Pa) or ``mean_mm = 8.5`` meant in um. A real alternative material or fit
    differs by a factor of a few."""
    design, unc = config.design, config.uncertainty
    if design is None or unc is None:
        return []
    specs = {spec.name: spec for spec in unc.all_specs()}
    given = [(f"design.properties[{p.variable}].classes[{c.name}]", p.variable, c.mean)
             for p in design.properties for c in p.classes]
    given += [(f"design.materials[{m.name}].options[{o.name}].variables.{name}", name, spec.mean)
              for m in design.materials for o in m.options for name, spec in o.variables.items()]
    for fit in design.fits():
        fitted = fit.clearance(unc)
        if fitted is not None:
            where = "design.fit" if fit is design.fit else f"design.fit[{fitted.name}]"
            given += [(f"{where}.options[{o.name}]", fitted.name, _fit_mean(o, fitted)) for o in fit.options]
    out = []
    reach = population_reach(config.reliability.n_mc)
    for where, name, mean in given:
        base = specs.get(name)
        if base is None or mean is None or not base.mean or not mean:
            continue
        ratio = abs(mean / base.mean)
        mean_text, study_mean = shown(mean, base.target), shown(base.mean, base.target)
        sigmas = abs(mean - base.mean) / base.std if getattr(base, "std", None) else 0.0
        if not 1.0 / DESIGN_SCALE_WARNING <= ratio <= DESIGN_SCALE_WARNING:
            out.append(f"{where}: its mean ({mean_text}) is {ratio:.3g} times the study's mean of "
                       f"'{name}' ({study_mean}): a unit slip? (a suffix gives the unit: mean_HB, mean_um)")
        elif sigmas > reach:
            out.append(f"{where}: its mean ({mean_text}) lies {sigmas:.3g} of the study's standard "
                       f"deviations from its mean of '{name}' ({study_mean}), beyond the {reach:.2g} its "
                       f"population of {config.reliability.n_mc:,} reaches: the design judges it by extrapolation, and "
                       "a rejected option is never verified; widen the study's distribution of it to cover the "
                       "option, or run a study of the option (docs/design.md, 'Limits')")
    out += _fit_correlation_warnings(design, unc)
    rel = config.reliability
    first, last = rel.cycles_start, rel.cycles_stop
    for i, target in enumerate(design.targets):
        n = target.life_cycles
        if n is not None and first is not None and last is not None and not first <= n <= last:
            out.append(f"design.targets[{i}].life_cycles: {n:,.0f} cycles lies {'before' if n < first else 'beyond'} "
                       f"the R(N) curve ({first:,}-{last:,} cycles), where the study's learning has not refined "
                       "the surrogate, so the design judges it there; put the curve round the target "
                       "(reliability.cycles_start, cycles_stop; docs/design.md, 'Limits')")
    least = 2 * len(unc.all_specs()) + 2
    if design.verification_max_calls < least:
        out.append(f"design.verification_max_calls: {design.verification_max_calls} calls are fewer than the "
                   f"verification's initial design of 2d + 2 = {least} points (d = {least // 2 - 1} random inputs): "
                   "it is cut to the budget, and a Kriging of fewer points than about twice the dimension can be "
                   "sure of itself where it is wrong, so its verdict may not hold; give at least "
                   f"{least} (80 by default)")
    return out


def _fit_correlation_warnings(design, unc) -> list[str]:
    """A fit control whose clearance is correlated with another random input (a pin radius whose grade the fit
    sets): the options change the clearance's spread only, while that input keeps its spread and the correlation
    coefficient, both set from the study's fit (c = (D - d) / 2 gives corr(R_j, c) = -s_Rj / s_c)."""
    corr = unc.correlation
    if corr is None:
        return []
    names = corr.names()
    matrix = corr.full_matrix(names)
    out = []
    for fit in design.fits():
        fitted = fit.clearance(unc)
        if fitted is None or fitted.name not in names:
            continue
        i = names.index(fitted.name)
        partners = [f"'{n}' ({matrix[i, j]:+.3g})" for j, n in enumerate(names) if j != i and matrix[i, j] != 0.0]
        if partners:
            where = "design.fit" if fit is design.fit else f"design.fit[{fitted.name}]"
            out.append(f"{where}: its options change the spread of '{fitted.name}' only; the inputs correlated with "
                       f"it, {', '.join(partners)}, keep their spread and correlation as the study set them, though a "
                       "fit that changes the pin's grade changes the pin radius's spread and that correlation too; "
                       "set those inputs for the chosen fit in a study of it to check (docs/design.md, 'Limits')")
    return out


def config_warnings(config: StudyConfig) -> list[str]:
    """What is legal but probably not meant: a random variable whose mean lies more than
    ``MEAN_SHIFT_WARNING_SIGMAS`` standard deviations from the value drawn at its target (the nominal stages
    (simulate, wear) run the drawn mechanism and the reliability stages sample around the mean, so they would
    describe two different mechanisms), a drawn gap the assembly closes (:func:`drawing_warnings`), and the design
    specifications of :func:`design_warnings`."""
    from jointwear.uncertainty.targets import target_value

    mechanism = (drawing_warnings(config) + size_warnings(config) + clearance_size_warnings(config)
                 + transmission_warnings(config) + mobility_warnings(config)
                 + gravity_warnings(config) + speed_warnings(config) + inertia_warnings(config)
                 + friction_warnings(config))
    wear = (wear_length_warnings(config) + wear_mode_warnings(config) + half_width_warnings(config)
            + block_warnings(config))
    unc = config.uncertainty
    if unc is None:
        return mechanism + wear
    data = config.model_dump()
    out = []
    for spec in unc.all_specs():  # each target exists: StudyConfig checks them (_targets_exist)
        drawn = target_value(data, spec.target)
        shift = (spec.mean - drawn) / spec.std
        if abs(shift) > MEAN_SHIFT_WARNING_SIGMAS:
            out.append(f"uncertainty: the mean of '{spec.name}' ({shown(spec.mean, spec.target)}) is {abs(shift):,.2g} "
                       f"standard deviations from the value drawn at its target {spec.target} "
                       f"({shown(drawn, spec.target)}): the "
                       "simulate and wear stages run the drawn mechanism, the reliability stages one around the mean "
                       "(R(N) does not follow a change of the drawn value alone); give both the same value unless the "
                       "shift is meant")
    return (mechanism + out + scatter_warnings(config) + random_input_warnings(config) + clearance_warnings(config)
            + wear + design_warnings(config) + allowance_warnings(config) + budget_warnings(config)
            + target_warnings(config)
            + trend_warnings(config) + display_unit_warnings(config))


def friction_warnings(config: StudyConfig) -> list[str]:
    """Each clearance joint whose static friction coefficient is below its sliding one: friction then rises with the
    slip speed, which few material pairs do, and setting mu_d alone keeps the default mu_s."""
    default_mu_s = FrictionConfig.model_fields["mu_s"].default
    rising = [f"clearance_joints.{cj.name}.friction.mu_s: {cj.friction.mu_s:g} is below mu_d = {cj.friction.mu_d:g}, "
              "so friction rises from static to sliding; most material pairs have mu_s >= mu_d (mu_d given alone keeps "
              f"the default mu_s = {default_mu_s:g})"
              for cj in config.clearance_joints if cj.friction.law != "none" and cj.friction.mu_s < cj.friction.mu_d]
    # dry metal pairs slide at 0.1-0.8, clean ones in vacuum up to about 1; beyond, a percentage or a typo
    high = [f"clearance_joints.{cj.name}.friction.mu_d: {cj.friction.mu_d:g} is above {MU_D_WARNING:g}, beyond a "
            "sliding friction coefficient of dry metals (0.1-0.8); a percentage or a typo?"
            for cj in config.clearance_joints if cj.friction.law != "none" and cj.friction.mu_d > MU_D_WARNING]
    return rising + high


#: a sliding friction coefficient above this is warned (dry metal pairs: 0.1-0.8)
MU_D_WARNING = 1.0


#: what the wear stage says when it has no length for the nominal history
WEAR_CYCLES_MISSING = ("wear.cycles: give the number of cycles of the nominal wear history ([wear] cycles, or "
                       "--cycles N / cycles=N for one run) or an R(N) curve ([reliability] cycles_stop) whose end it "
                       "defaults to")


#: how the warning of a config without a wear length begins
WEAR_CYCLES_NEEDED = "wear.cycles: the wear stage will need the number"


def wear_length_warnings(config: StudyConfig) -> list[str]:
    """A config with clearance joints but no length for the nominal wear history: the wear stage then needs the
    caller's (``--cycles``); check and simulate run without it."""
    if config.clearance_joints and nominal_wear_cycles(config) is None:
        return [WEAR_CYCLES_MISSING.replace("wear.cycles: give the number", WEAR_CYCLES_NEEDED)]
    start, stop = config.reliability.cycles_start, config.reliability.cycles_stop
    n = config.wear.cycles
    if config.clearance_joints and n is not None and start is not None and n < start:
        return [f"wear.cycles: the nominal history ends at {n:,} cycles, before the R(N) curve's first level "
                f"({start:,}): the nominal wear the report shows is that of {n:,} cycles and the nominal life is "
                f"extrapolated past the history's end; set wear.cycles = {stop:,}, the curve's end (inherited from "
                "a preset, it may be the preset's)"]
    return []


def drawing_warnings(config: StudyConfig) -> list[str]:
    """The joints of a general linkage whose drawn gap (two points of a revolute joint apart, a prismatic joint's
    point off its guide) is more than ``GAP_WARNING`` of the median link size but within ``closure_tolerance`` of it:
    the assembly closes such a gap without a word, so the links it joins are not as drawn (a misplaced point, most
    likely)."""
    from jointwear.mechanism.assembly import GAP_WARNING, drawn_link_size, gap_text, joint_gaps

    m = config.mechanism
    if m.type != "general":
        return []
    size = drawn_link_size([b.points.values() for b in m.bodies])
    names = [j.name for j in m.joints]
    return [f"mechanism.joints[{item_key(i, names)}].connects: {gap_text(joint, gap)}; the assembly closes the gap, "
            "so the links it joins are up to that much off the drawing: "
            + ("draw the two points at the same place" if joint.type == "revolute" else "draw the point on the guide")
            + " unless that is meant"
            for i, joint, gap in joint_gaps(m) if GAP_WARNING * size < gap <= m.closure_tolerance * size]


def drawn_links(mechanism) -> list[tuple[str, Any, float]]:
    """The moving links as (where the config names it, its settings, its drawn size): a general body's size is the
    largest distance between two of its points, a four-bar's or slider-crank's link's its length."""
    if mechanism.type == "general":
        return [(f"mechanism.bodies[{b.name}]", b,
                 max((math.dist(p, q) for p in b.points.values() for q in b.points.values()), default=0.0))
                for b in mechanism.bodies]
    return [(f"mechanism.{name}", link, link.length)
            for name in ("crank", "rod", "rocker") if (link := getattr(mechanism, name, None)) is not None]


#: a bearing narrower than this share of its journal's diameter, or a journal smaller than this share of the largest
#: link, is far outside any pin joint's proportions (width / diameter runs 0.25-2): most likely a unit slip
NARROW_BEARING = 0.05
SMALL_JOINT = 1e-4


def size_warnings(config: StudyConfig) -> list[str]:
    """Lengths out of scale with the drawing, most likely a unit slip (metres under a _mm key, or the reverse): a
    clearance joint's journal, bore or width larger than the largest link, a journal smaller than ``SMALL_JOINT`` of
    it, a width below ``NARROW_BEARING`` of the journal's diameter, and a general body's centre of mass
    farther from every point of the body than the body is long."""
    m = config.mechanism
    links = drawn_links(m)
    largest = max((size for _, _, size in links), default=0.0)
    out = []
    names = [cj.name for cj in config.clearance_joints]
    for i, cj in enumerate(config.clearance_joints):
        where = f"clearance_joints[{item_key(i, names)}]"
        sizes = {"journal_radius": cj.journal_radius, "bearing_radius": cj.bearing_radius, "width": cj.width,
                 "bearing_outer_radius": cj.bearing_outer_radius}
        too_big = [name for name, value in sizes.items() if value is not None and largest > 0.0 and value > largest]
        if too_big:
            out.append(f"{where}: {', '.join(f'{n} {sizes[n] * 1e3:,.4g} mm' for n in too_big)}, "
                       f"larger than the mechanism's largest link ({largest * 1e3:.4g} mm): a unit slip? (a suffix "
                       f"gives the unit: {too_big[0]}_mm)")
        if not too_big and largest > 0.0 and cj.journal_radius < SMALL_JOINT * largest:
            out.append(f"{where}: journal_radius {cj.journal_radius * 1e3:.4g} mm, less than "
                       f"{SMALL_JOINT:g} of the mechanism's largest link ({largest * 1e3:.4g} mm): a unit slip? "
                       "(metres under a _mm key)")
        if not too_big and cj.width < NARROW_BEARING * 2.0 * cj.journal_radius:
            out.append(f"{where}: width {cj.width * 1e3:.4g} mm, less than {NARROW_BEARING:g} of the "
                       f"journal's diameter ({2e3 * cj.journal_radius:.4g} mm; pin joints run 0.25 to 2): a unit slip? "
                       "(a suffix gives the unit: width_mm)")
    if m.type == "general":
        for where, b, size in links:
            if len(b.points) < 2 or size <= 0.0:
                continue
            nearest = min(math.dist(b.com, q) for q in b.points.values())
            if nearest > size:
                out.append(f"{where}.com: {nearest * 1e3:.4g} mm from the nearest of the body's points, farther than "
                           f"the body is long ({size * 1e3:.4g} mm): a unit slip or a misplaced point? (com is in "
                           "global coordinates, as the points are)")
    return out


#: a radial clearance above this share of the journal radius is warned (project choice: the loosest ISO 286 running
#: fits give about 1.5 % at 10 mm and Flores' slider-crank benchmark 5.3 %; the model's pin in a bore holds for any
#: clearance, but one this loose is a slip more often than a design)
CLEARANCE_RATIO_WARNING = 0.10


def clearance_size_warnings(config: StudyConfig) -> list[str]:
    """A radial clearance that is a large share of the journal radius: a diameter given for a radius, or mm for um,
    runs as a loose joint whose linkage no longer follows its crank, with ordinary-looking forces."""
    out = []
    for cj in config.clearance_joints:
        c = cj.bearing_radius - cj.journal_radius
        if c > CLEARANCE_RATIO_WARNING * cj.journal_radius:
            out.append(f"clearance_joints.{cj.name}: the radial clearance, {c * 1e3:.4g} mm (bearing_radius - "
                       f"journal_radius), is {100 * c / cj.journal_radius:.3g} % of the journal radius, more than "
                       f"{100 * CLEARANCE_RATIO_WARNING:g} %: running fits give 0.1-1.5 % and the clearance benchmarks "
                       "of the literature about 5 %, and a joint this loose lets the linkage stray from its crank: a "
                       "diameter given for a radius, or mm written for um?")
    return out


#: the transmission angle's band outside which a linkage is warned, deg (project choice: design practice keeps it
#: within 40-140 deg, e.g. Norton, Design of Machinery, section 4.10; 30-150 at the least)
TRANSMISSION_ANGLE_WARNING_DEG = (30.0, 150.0)


def transmission_range(mechanism) -> tuple[float, float] | None:
    """(min, max) transmission angle over a crank turn, deg: a four-bar's between rod and rocker, by the law of
    cosines at the extreme distances d -+ l1 from crank pin to rocker pivot; a slider-crank's between rod and the
    slider's path's normal, 90 - asin((l1 + |e|) / l2) at its least (so its max is 90). None for a general linkage."""
    if mechanism.type == "four_bar":
        l1, l2, l3 = mechanism.crank.length, mechanism.rod.length, mechanism.rocker.length
        d = math.dist(mechanism.rocker_pivot, mechanism.crank_pivot)
        angle = [math.degrees(math.acos((l2 * l2 + l3 * l3 - ac * ac) / (2.0 * l2 * l3))) for ac in (d - l1, d + l1)]
        return min(angle), max(angle)
    if mechanism.type == "slider_crank":
        reach = (mechanism.crank.length + abs(mechanism.offset)) / mechanism.rod.length
        return 90.0 - math.degrees(math.asin(min(reach, 1.0))), 90.0
    return None


#: the smallest ratio sv_min / sv_max of a general linkage's scaled constraint Jacobian over its assembly sweep below
#: which it is warned of as passing near a dead point: calibrated on general four-bars and slider-cranks to warn at
#: 10 deg of transmission angle and not at 30, with the six-bar preset's 0.095 clear (docs/dynamics.md, "Dead points")
DEAD_POINT_RATIO_WARNING = 0.06


def dead_point_warnings(config: StudyConfig) -> list[str]:
    """A general linkage, driven with no free degree of freedom, whose assembly sweep comes near a dead point: the
    smallest ratio sv_min / sv_max of its scaled constraint Jacobian over the cycle (recorded by the assembly,
    :class:`jointwear.mechanism.assembly.DeadPointMargin`) below ``DEAD_POINT_RATIO_WARNING``, the counterpart of
    the four-bar's transmission-angle rule (a general four-bar 0.4 deg from a dead point passed silently, then
    simulated a 39 kN peak against a 231 N mean)."""
    m = config.mechanism
    if m.type != "general" or m.free_degrees_of_freedom() > 0:
        return []
    from jointwear.mechanism.assembly import general_parts

    try:
        margin = general_parts(m).dead_point
    except ConfigError:  # the assembly check reports it
        return []
    if margin is None or margin.ratio >= DEAD_POINT_RATIO_WARNING:
        return []
    driver = m.drivers[0].joint
    return [f"mechanism: the linkage passes near a dead point at links {', '.join(margin.links)}, when the first "
            f"driver (joint '{driver}') is at {margin.driver_angle_deg:.4g} deg ({margin.turn_deg:+.4g} deg from the "
            f"drawing): the constraint Jacobian's smallest singular value falls to {margin.ratio:.3g} of its largest "
            f"there, below {DEAD_POINT_RATIO_WARNING:g} (a four-bar with a transmission angle of about 14-21 deg; 0 "
            "is the dead point). Near a dead point the joint forces grow without bound, so the peaks, the clearance "
            "joints' impacts and their wear climb there: lengthen or shorten those links, or move their pivots, to "
            "keep the linkage away from the position where they line up (docs/dynamics.md, 'General linkages')"]


def transmission_warnings(config: StudyConfig) -> list[str]:
    """A four-bar or slider-crank whose transmission angle leaves 30-150 deg: its joint forces grow as 1 / sin of the
    angle, so the peaks, the impacts of a clearance joint and its wear climb near such a position (a 13-deg linkage
    ran without a word at peaks of 1.4 kN); a general linkage near a dead point (:func:`dead_point_warnings`)."""
    span = transmission_range(config.mechanism)
    low, high = TRANSMISSION_ANGLE_WARNING_DEG
    if span is None:
        return dead_point_warnings(config)
    if low <= span[0] and span[1] <= high:
        return []
    return [f"mechanism: the transmission angle ranges over {span[0]:.3g}-{span[1]:.3g} deg in a crank turn, beyond "
            f"{low:g}-{high:g} deg: the joint forces grow as 1 / sin of it, so peaks and the clearance joints' "
            "impacts climb near the extreme; design practice keeps it within 40-140 deg"]


def mobility_warnings(config: StudyConfig) -> list[str]:
    """A general linkage that keeps degrees of freedom after its drivers: legal (a pendulum swings under its load),
    but a forgotten joint gives the same, and a silently different mechanism; and a swing nothing in the model damps
    keeps the amplitude its start gave it (benchmarks/wear.py `profile_rig_start_phase`)."""
    m = config.mechanism
    if m.type != "general" or (dof := m.free_degrees_of_freedom()) <= 0:
        return []
    return [f"mechanism: the linkage keeps {dof} degree{'s' if dof > 1 else ''} of freedom after its drivers (3 per "
            "free body, less 2 per joint): some bodies move only under their loads, as a pendulum does; if none "
            "should, a joint is missing (a slider's prismatic joint, say). Nothing in the model damps such a swing, "
            "so where a joint wears in uniform mode can depend on how its history starts: `jointwear converge` "
            "measures that scatter (docs/wear.md, 'A swing nothing damps')"]


#: Gravity larger than this (m/s^2) is warned as a likely unit slip (mm/s^2 under an _m_s2 key): 10 g
GRAVITY_WARNING = 10 * 9.80665


def gravity_warnings(config: StudyConfig) -> list[str]:
    """A gravity vector far larger than the earth's: most likely mm/s^2 written where m/s^2 was meant."""
    gravity = getattr(config.mechanism, "gravity", None)
    magnitude = 0.0 if gravity is None else math.hypot(*gravity)
    if magnitude <= GRAVITY_WARNING:
        return []
    return [f"mechanism.gravity: {magnitude:,.6g} m/s^2 is {magnitude / 9.80665:,.0f} g (a unit slip? gravity_m_s2 "
            "takes m/s^2, 9.80665 on earth)"]


#: A crank faster than this (rad/s, about 9,500 rpm) is warned as a likely number of rpm written without its suffix:
#: linkages with clearance joints run well below it (the presets at 480 and 5,000 rpm), and 1,450 read as rad/s is
#: 13,846 rpm.
CRANK_SPEED_WARNING = 1000.0


def speed_warnings(config: StudyConfig) -> list[str]:
    """A crank speed above ``CRANK_SPEED_WARNING``: most likely rpm written where rad/s is read (no suffix)."""
    from jointwear.units import SUFFIXES

    speed = abs(float(getattr(config.mechanism, "crank_speed", 0.0) or 0.0))
    if speed <= CRANK_SPEED_WARNING:
        return []
    field = "drivers[0].speed" if hasattr(config.mechanism, "drivers") else "crank_speed"
    rpm = speed / SUFFIXES["rpm"][0]
    return [f"mechanism.{field}: {speed:,.6g} rad/s is {rpm:,.0f} rpm (a unit slip? a number without a suffix is "
            f"read as rad/s: write {field.split('.')[-1]}_rpm = {speed:,.6g} if rpm was meant)"]


#: Radii of gyration sqrt(I / m) outside these fractions of a link's drawn size are warned as a likely unit slip: a
#: uniform bar has 0.29, a link's material cannot all lie within 2 % of its size of the centre of mass, and a
#: flywheel on a crank reaches a few times the crank's length, not ten.
GYRATION_RANGE = (0.02, 10.0)


def inertia_warnings(config: StudyConfig) -> list[str]:
    """The moving links whose mass and moment of inertia give a radius of gyration outside ``GYRATION_RANGE`` of
    their drawn size (a general body: the largest distance between two of its points; a four-bar's or
    slider-crank's link: its length): a mass given in kg where g was meant passed every check."""
    out = []
    low, high = GYRATION_RANGE
    for where, link, size in drawn_links(config.mechanism):
        if size <= 0.0:
            continue
        mass, inertia = link.mass, link.inertia
        k = math.sqrt(inertia / mass)
        if not low * size <= k <= high * size:
            out.append(f"{where}: its mass ({mass * 1e3:.4g} g) and inertia ({inertia * 1e9:.4g} g mm^2) give a radius "
                       f"of gyration of {k * 1e3:.3g} mm, {k / size:.2g} times its size ({size * 1e3:.3g} mm; a "
                       "uniform bar has 0.29): a unit slip? (a suffix gives the unit: mass_g, inertia_g_mm2)")
    return out


def budget_warnings(config: StudyConfig) -> list[str]:
    """A call budget too small for the learning ever to stop on its rule: the rule can first hold on the initial
    design, and each of the ``hold_iterations`` - 1 designs that must confirm it adds a batch."""
    rel = config.reliability
    needed = rel.n_initial + rel.batch_size * (rel.hold_iterations - 1)
    if config.uncertainty is None or rel.max_calls >= needed:
        return []
    return [f"reliability.max_calls: {rel.max_calls} calls cannot confirm the learning's stop, which needs at least "
            f"{needed} (n_initial = {rel.n_initial}, then {rel.hold_iterations - 1} batches of {rel.batch_size} for "
            f"hold_iterations = {rel.hold_iterations}): the learning will end on its budget, unconverged; raise "
            "max_calls, or lower hold_iterations"]


def trend_warnings(config: StudyConfig) -> list[str]:
    """``reliability.trend = "archard"`` where it changes nothing: no random wear coefficient or hardness of the judged
    body of a single judged joint, so the Kriging has no known part to be told."""
    rel = config.reliability
    if rel.trend != "archard" or config.uncertainty is None or archard_trend_applies(config):
        return []
    limit = limit_state_from_config(config)
    body = {"bearing_max_depth": "bearing", "journal_max_depth": "journal"}.get(rel.quantity)
    why = (f"it needs one judged joint (judged: {', '.join(limit.names)})" if len(limit.joints) != 1 else
           f"reliability.quantity = {rel.quantity!r} is not one body's wear depth" if body is None else
           f"no random variable targets clearance_joints.{limit.names[0]}.{body}_material.wear_coefficient or "
           ".hardness")
    return [f"reliability.trend: 'archard' changes nothing here, the Kriging learns ln N_f with a constant trend: "
            f"{why} (docs/reliability.md, \"The learnt life's spread\")"]


def target_warnings(config: StudyConfig) -> list[str]:
    """Each target reliability whose Pf = 1 - R the curve cannot estimate to its COV target: below ``pf_floor``
    (the COV target is waived there), or needing more samples than ``n_mc_max`` (COV^2 = (1 - Pf) / (n Pf))."""
    from jointwear.reliability.results import cov_population

    rel = config.reliability
    if config.uncertainty is None:
        return []
    out = []
    for target in rel.targets:
        pf = 1.0 - target
        needed = cov_population(pf, rel.cov_target)
        waived = pf < rel.pf_floor * (1.0 - 1e-9)  # (1 - 0.9999 is 9.9999999999998e-05) not grown for: may stay at n_mc
        if not waived and needed <= rel.n_mc_max * (1.0 + 1e-9):
            continue
        cov = math.sqrt((1.0 - pf) / (pf * (rel.n_mc if waived else rel.n_mc_max)))
        why = (f"below pf_floor = {rel.pf_floor:g}, where the COV target is waived" if waived
               else f"beyond n_mc_max = {rel.n_mc_max:,}")
        if needed <= MAX_MC_SAMPLES:
            remedy = f"set pf_floor <= {pf:.3g} and n_mc_max >= {needed:,.0f}"
        else:  # the advice must be one the config takes
            reachable = math.sqrt((1.0 - pf) / (pf * MAX_MC_SAMPLES))
            remedy = (f"set pf_floor <= {pf:.3g} and n_mc_max = {MAX_MC_SAMPLES:,} (the largest population, which "
                      f"reads it to a COV of {reachable:.2g}; the COV target needs {needed:,.0f} samples)")
        out.append(f"reliability.target_reliability: the life at R = {target:g} reads the curve at Pf = {pf:.3g}, "
                   f"{why}: its Monte Carlo COV may reach {cov:.2g} (target {rel.cov_target:g}), and its interval "
                   f"widens with it. For it, {remedy}, and a cycles_start early enough for the curve to reach that R "
                   "(a validation of N samples cannot test R above about 1 - 3.7 / N)")
    return out


def allowance_warnings(config: StudyConfig) -> list[str]:
    """Each judged joint whose allowance cannot be checked against what the joint can wear (no
    ``bearing_outer_radius``, so no :func:`~jointwear.study.limit_state.wearable_stock`; an allowance at or beyond
    it is refused by :func:`~jointwear.study.limit_state.limit_state_problems`) and is at least
    ``ALLOWANCE_CLEARANCE_WARNING`` times the joint's clearance: the sign of a unit slip (5 mm meant as 5 um)."""
    if limit_state_problems(config):
        return []
    rel = config.reliability
    state = limit_state_from_config(config)
    out = []
    for i, name, allowance in zip(state.joints, state.names, state.allowances):
        joint = config.clearance_joints[i]
        if wearable_stock(rel.quantity, joint) is not None or allowance < ALLOWANCE_CLEARANCE_WARNING * joint.clearance:
            continue
        where = f"reliability.allowances.{name}" if name in rel.allowances else "reliability.allowance"
        out.append(f"{where}: {allowance * 1e3:.6g} mm for joint {name} is {allowance / joint.clearance:.3g} times "
                   f"its clearance ({joint.clearance * 1e3:.6g} mm), and without clearance_joints.{name}."
                   "bearing_outer_radius it cannot be checked against the bearing's wall: a unit slip? (without a "
                   "suffix the allowance is in m: allowance_mm, allowance_um); give the outer radius to have it "
                   "checked")
    return out


#: Dynamics cycles one wear history may simulate before check warns of its cost: at the 1.5-8 ms a cycle of the
#: shipped presets and examples (docs/wear.md), 10,000 cycles take 0.25-1.3 minutes per model call (a 560,000-cycle
#: history in the default 10,000-cycle blocks simulates 168).
LONG_HISTORY_SIMULATED_CYCLES = 10_000


def block_warnings(config: StudyConfig) -> list[str]:
    """A fixed block as long as the nominal history or longer: the whole history is then one straight block at the
    unworn geometry's rate, and halving the block (``jointwear converge``) changes nothing while it stays that long.
    Blocks so short that a history simulates more than ``LONG_HISTORY_SIMULATED_CYCLES`` cycles of dynamics (each
    block settles ``settle_cycles`` and records ``record_cycles``): every model call pays them."""
    wear, n = config.wear, nominal_wear_cycles(config)
    if wear.block_rule != "fixed" or n is None:
        return []
    if wear.block_cycles >= n:
        return [f"wear.block_cycles: {wear.block_cycles:,} cycles is at least the nominal history's {n:,}: the "
                "history is one block, extrapolated straight at the unworn geometry's wear rate; take shorter blocks "
                "(jointwear converge says which size is converged)"]
    blocks = math.ceil(n / wear.block_cycles)
    simulated = wear.simulated_cycles(n)
    if simulated <= LONG_HISTORY_SIMULATED_CYCLES:
        return []
    return [f"wear.block_cycles: {wear.block_cycles:,} cycles makes the nominal history of {n:,} cycles {blocks:,} "
            f"blocks, which simulate {simulated:,.0f} cycles of dynamics ({wear.settle_cycles:g} settling and "
            f"{wear.record_cycles} recorded each), every model call: at the 1.5-8 ms a cycle of the shipped presets "
            f"and examples, about {simulated * 0.0015 / 60:,.0f}-{simulated * 0.008 / 60:,.0f} minutes a call; take "
            "longer blocks (jointwear converge says whether they are converged)"]


def wear_mode_warnings(config: StudyConfig) -> list[str]:
    """Wear settings moved from their defaults that the config's geometry mode (or profile deposit) does not read:
    a setting that silently changes nothing."""
    wear = config.wear
    given = {name for name, info in type(wear).model_fields.items() if getattr(wear, name) != info.default}
    mode = wear.geometry_mode
    unread = []
    if mode == "uniform":
        unread += [(name, "geometry_mode = 'profile'") for name in sorted(given) if name.startswith("profile_")]
    else:
        unread += [(name, "geometry_mode = 'uniform'") for name in sorted(given) if name.startswith("uniform_")]
        if wear.profile_deposit == "touch" and "profile_substep_cycles" in given:
            unread.append(("profile_substep_cycles", "profile_deposit = 'distributed'"))
        if "pressure" in given:  # profile mode reads the pressure off the worn shape
            unread.append(("pressure", "geometry_mode = 'uniform'"))
    return [f"wear.{name}: read only with {needed}; this study runs geometry_mode = '{mode}'"
            + (f" with profile_deposit = '{wear.profile_deposit}'" if mode == "profile" else "")
            + ", so the setting changes nothing" for name, needed in unread]


#: a half-width factor more than this many times Johnson's, or less than its inverse, is warned (project choice: the
#: paper's reading, 1.596, is 1.41 times Johnson's)
HALF_WIDTH_FACTOR_WARNING = 2.0


def half_width_warnings(config: StudyConfig) -> list[str]:
    """A contact half-width factor far from Johnson's sqrt(4/pi): the patch, hence how the wear is spread and the
    conformity indicator, scale with it; a factor of 100 passed silently and read as a soft bushing."""
    from jointwear.wear.settings import JOHNSON_FACTOR

    ratio = config.wear.half_width_factor / JOHNSON_FACTOR
    if 1.0 / HALF_WIDTH_FACTOR_WARNING <= ratio <= HALF_WIDTH_FACTOR_WARNING:
        return []
    return [f"wear.half_width_factor: {config.wear.half_width_factor:g} is {ratio:.3g} times Johnson's line-contact "
            f"factor sqrt(4/pi) = {JOHNSON_FACTOR:.4g} (the paper's reading is 1.596): the contact patch, how the wear "
            "is spread over it and the conformity indicator scale with it; leave it at the default unless such a "
            "patch is meant"]


def clearance_warnings(config: StudyConfig) -> list[str]:
    """Each clearance whose normal lies so far below ``minimum`` that the truncation there moves the sampled mean
    by more than ``TRUNCATED_MEAN_SHIFT_WARNING`` of the designed mean (the study then describes another fit), and
    each whose ISO 286 tolerances are taken at a nominal diameter that gives other ones than its journal's
    (:func:`nominal_diameter_warning`)."""
    if config.uncertainty is None:
        return []
    several = isinstance(config.uncertainty.clearance, list)
    data = config.model_dump()
    out = []
    for clearance in config.uncertainty.clearances():
        where = f"uncertainty.clearance[{clearance.name}]" if several else "uncertainty.clearance"
        if (diameter := nominal_diameter_warning(data, clearance)) is not None:
            out.append(f"{where}.{diameter}")
        if (pin := pin_scatter_warning(config.uncertainty, clearance)) is not None:
            out.append(f"{where}: {pin}")
        if clearance.infeasible_rule != "truncate":
            continue
        sampled = float(clearance.feasible().mean())
        if abs(sampled - clearance.mean) <= TRUNCATED_MEAN_SHIFT_WARNING * clearance.mean:
            continue
        out.append(f"{where}: {clearance.infeasible_probability():.1%} of the clearance's normal "
                   f"(mean {clearance.mean * 1e6:.4g} um, std {clearance.std * 1e6:.4g} um) lies at or below its "
                   f"minimum ({clearance.minimum * 1e6:.4g} um); the samples are truncated there, so their mean is "
                   f"{sampled * 1e6:.4g} um, not the designed {clearance.mean * 1e6:.4g} um: choose a fit whose "
                   "spread suits the clearance, or infeasible_rule = 'fail' to count those assemblies as failures")
    return out


def pin_scatter_warning(uncertainty, clearance) -> str | None:
    """The pin radius drawn with the spread of the clearance's own shaft grade (T_d / 12, within 5 %) and independent
    of the clearance: c = (D - d) / 2 already holds the pin's scatter, so the bore radius R_j + c scatters by
    sqrt(s_Rj^2 + s_c^2) instead of the hole grade's T_D / 12. A bore and a pin made apart are drawn right with
    corr(R_j, c) = -s_Rj / s_c (Var(R_b) = s_c^2 - s_Rj^2 = (T_D / 12)^2); clearances matched at assembly are not
    warned of unless their pin's spread is the shaft grade's."""
    from jointwear.uncertainty.targets import CLEARANCE_SUFFIX
    from jointwear.uncertainty.tolerances import it_tolerance

    if clearance.source != "iso286" or not clearance.target.endswith(CLEARANCE_SUFFIX):
        return None
    radius = clearance.target[: -len(CLEARANCE_SUFFIX)] + ".journal_radius"
    pin = next((v for v in uncertainty.all_specs() if v.target == radius), None)
    if pin is None:
        return None
    shaft = it_tolerance(clearance.shaft_grade, clearance.nominal_diameter) / 12.0
    correlation = uncertainty.correlation_matrix([pin.name, clearance.name])
    if abs(pin.std - shaft) > 0.05 * shaft or (correlation is not None and correlation[0, 1] != 0.0):
        return None
    rho = -pin.std / clearance.std
    return (f"the pin radius '{pin.name}' scatters by {pin.std * 1e6:.3g} um, its shaft grade's "
            f"({clearance.shaft_grade} / 12), which the clearance's spread already holds: drawn independently, the "
            f"bore radius R_j + c scatters by {math.hypot(pin.std, clearance.std) * 1e6:.3g} um, not the hole grade's "
            f"{math.sqrt(max(clearance.std ** 2 - pin.std ** 2, 0.0)) * 1e6:.3g} um; for a bore and a pin made "
            f"apart correlate them: [uncertainty.correlation] pairs = [['{pin.name}', '{clearance.name}', "
            f"{rho:.3g}]]")


def nominal_diameter_warning(data: dict, clearance) -> str | None:
    """'nominal_diameter: ...' when the clearance's ISO 286 spread (and a fit's mean) at its nominal diameter differ
    by more than 1 % from those at its joint's journal diameter 2 R_j (its default): a diameter in another size range
    of ISO 286-2 has other tolerances."""
    from jointwear.uncertainty.targets import CLEARANCE_SUFFIX, target_error, target_value
    from jointwear.uncertainty.tolerances import clearance_from_fit, iso_fit

    if clearance.source != "iso286" or not clearance.target.endswith(CLEARANCE_SUFFIX) or target_error(
            data, clearance.target):
        return None
    joint = clearance.target[: -len(CLEARANCE_SUFFIX)]
    journal = 2.0 * target_value(data, f"{joint}.journal_radius")
    try:
        at_journal = (iso_fit(clearance.fit, journal).mean_clearance if clearance.fit is not None
                      else clearance.mean)
        std = clearance_from_fit(journal, clearance.hole_grade, clearance.shaft_grade, at_journal).std
    except ValueError:  # outside ISO 286's sizes: the fit's own check says so
        return None
    if abs(std - clearance.std) <= 0.01 * clearance.std and abs(at_journal - clearance.mean) <= 0.01 * clearance.mean:
        return None
    mean = (f", mean {clearance.mean * 1e6:.4g} um" if clearance.fit is not None else "")
    mean_there = (f", mean {at_journal * 1e6:.4g} um" if clearance.fit is not None else "")
    nominal = f"{clearance.nominal_diameter * 1e3:g} mm"
    return (f"nominal_diameter: {nominal}, while the journal of {joint} is {journal * 1e3:.4g} mm in diameter: "
            f"the clearance takes the tolerances of {nominal} (std {clearance.std * 1e6:.3g} um{mean}), at "
            f"{journal * 1e3:.4g} mm they are std {std * 1e6:.3g} um"
            f"{mean_there}; set nominal_diameter_mm = {journal * 1e3:.6g} unless the fit's size is meant to differ")


def out_problem(out: Path) -> str | None:
    """Why ``out`` cannot become a writable folder, judged without creating anything (None when it looks fine):
    its nearest existing ancestor must be a folder this process may write to."""
    existing = Path(out).absolute()
    while not existing.exists():
        existing = existing.parent
    if not existing.is_dir():
        return f"out: cannot write to '{out}': '{existing}' is a file, not a folder"
    if not os.access(existing, os.W_OK | os.X_OK):
        return f"out: cannot write to '{out}': '{existing}' is not writable"
    return None


#: a random variable's ends checked by :func:`random_input_warnings`, in standard deviations from its mean
SIGMA_ENDS = 3.0


def unbuilt_reason(config: StudyConfig, targets: list[str], x: list[float]) -> str | None:
    """Why the model of ``config`` with ``targets`` set to ``x`` (SI) cannot be built, as a model call would
    record it (None when it builds)."""
    from jointwear.mechanism import build_model
    from jointwear.study.model_call import apply_sample

    try:
        build_model(apply_sample(config, targets, x))
    except ConfigError as exc:
        return "; ".join(exc.problems)
    except (ValueError, ArithmeticError) as exc:  # a number the model cannot use: a call would fail the same way
        return " ".join(str(exc).split())
    return None


def _unit_hint(config: StudyConfig, target: str, value: float) -> str:
    """' (a unit slip? ...)' when ``value`` is orders of magnitude from the value drawn at ``target``, else ''."""
    from jointwear.config import target_display_unit
    from jointwear.uncertainty.targets import target_value
    from jointwear.units import suffixes_of

    drawn = target_value(config.model_dump(), target)
    unit = target_display_unit(target)
    if not unit or not drawn or 1e-2 < abs(value / drawn) < 1e2:
        return ""
    return (f"; the config itself has {shown(drawn, target)} there: give the variable's numbers in their unit with a "
            f"suffix ({', '.join('mean_' + s for s in suffixes_of(unit))})")


def random_input_problems(config: StudyConfig) -> list[str]:
    """The random variables at whose means the model cannot be built (every call of the study would fail), each
    with the model's own reason; checked all at their means, then each alone to name the culprits."""

    unc = config.uncertainty
    if unc is None or not unc.all_specs():
        return []
    specs = unc.all_specs()
    means = [float(m.mean()) for m in unc.marginals(feasible=True)]  # the distributions as the study samples them
    together = unbuilt_reason(config, [s.target for s in specs], means)
    if together is None:
        return []
    out = []
    for spec, mean in zip(specs, means):
        reason = unbuilt_reason(config, [spec.target], [mean])
        if reason is not None:
            out.append(f"{unc.field_of(spec.name)}: at its mean, {shown(mean, spec.target)}"
                       + f", the model cannot be built, so every model call would fail: {reason}"
                       + _unit_hint(config, spec.target, mean))
    return out or [f"uncertainty: with every random variable at its mean ({', '.join(unc.names())}) the model "
                   f"cannot be built, so every model call would fail: {together}"]


def random_input_warnings(config: StudyConfig) -> list[str]:
    """Each random variable at whose +-``SIGMA_ENDS`` sigma end (the others at their means) the model cannot be
    built: those samples' calls fail. A failed call counts as a failure where the learning draws it, but the rest of
    the population there is classified by the surrogate's extrapolation (docs/study.md), so R(N) may read high."""
    from scipy.stats import norm

    unc = config.uncertainty
    if unc is None or not unc.all_specs() or random_input_problems(config):
        return []
    specs, marginals = unc.all_specs(), unc.marginals(feasible=True)
    targets = [s.target for s in specs]
    means = [float(m.mean()) for m in marginals]
    out = []
    for i, (spec, marginal) in enumerate(zip(specs, marginals)):
        for sign in (-1.0, 1.0):
            end = float(marginal.ppf(norm.cdf(sign * SIGMA_ENDS)))  # the same tail share of any distribution
            reason = unbuilt_reason(config, targets, means[:i] + [end] + means[i + 1:])
            if reason is not None:
                out.append(f"{unc.field_of(spec.name)}: at its {'+' if sign > 0 else '-'}{SIGMA_ENDS:g} sigma end, "
                           f"{shown(end, spec.target)}, the model cannot be built: {reason}; the samples beyond "
                           "it fail, and the study counts them as failures only where its model calls fall (the "
                           "surrogate extrapolates over the rest, so R(N) may read high): narrow the distribution, "
                           "or bound it (truncated_normal)")
                break
    return out


def display_unit_warnings(config: StudyConfig) -> list[str]:
    """Each random variable with a display unit jointwear does not convert (not a key suffix) and no scale: the
    report would show its SI numbers under that unit."""
    unc = config.uncertainty
    if unc is None:
        return []
    out = []
    for spec in unc.variables:
        si = target_display_unit(spec.target)
        if spec.unit and spec.scale == 1.0 and suffix_unit(spec.unit) is None and spec.unit != si:
            out.append(f"{unc.field_of(spec.name)}.unit: {spec.unit!r} is not a unit jointwear converts to, and scale "
                       f"is 1: the report shows the SI value{f' ({si})' if si else ''} under it; give scale (SI value "
                       "x scale = value in the unit), or a unit keys take as a suffix (mm, um, GPa, MPa, HB, ...)")
    return out


#: a random variable whose standard deviation is below this share of its mean barely varies: a unit slip (a
#: standard deviation given without its suffix is SI: 12 for 12 GPa reads 12 Pa, 1e-10 of a 120 GPa modulus)
TINY_SCATTER = 1e-6


def scatter_warnings(config: StudyConfig) -> list[str]:
    """Each random variable whose standard deviation is below ``TINY_SCATTER`` of its mean's magnitude."""
    from jointwear.config import target_display_unit

    unc = config.uncertainty
    if unc is None:
        return []
    out = []
    for spec, marginal in zip(unc.all_specs(), unc.marginals(feasible=True)):
        mean, std = float(marginal.mean()), float(marginal.std())
        if mean != 0.0 and std < TINY_SCATTER * abs(mean):
            si = target_display_unit(spec.target)
            out.append(f"{unc.field_of(spec.name)}: its standard deviation, {std:.3g}{f' {si}' if si else ''}, is "
                       f"{std / abs(mean):.2g} of its mean ({shown(mean, spec.target)}): the variable barely varies. "
                       "A unit slip? A number without a unit suffix is SI (std_GPa = 12 for 12 GPa)")
    return out


def unit_slip_warnings(config: StudyConfig) -> list[str]:
    """The warnings that name a likely unit slip of the mechanism: the likeliest cause of one that does not run."""
    return size_warnings(config) + inertia_warnings(config) + gravity_warnings(config)


def _first_unit_slip(config: StudyConfig) -> str:
    """'; check first <the first unit-slip warning> (and N more such warnings)', or '' without one: said with the
    failure, since the stage stops there before the warnings are told."""
    slips = unit_slip_warnings(config)
    if not slips:
        return ""
    return f"; check first {slips[0]}" + (f" (and {len(slips) - 1} more such warnings)" if len(slips) > 1 else "")


def check_runs(config: StudyConfig) -> list[str]:
    """The nominal mechanism assembles and its dynamics starts (a hundredth of a cycle)."""
    from jointwear.mechanism import SimulationError, build_model, simulate

    try:
        model = build_model(config)
    except ConfigError as exc:
        return [f"{exc}{_first_unit_slip(config)}"]
    try:
        simulate(model, 0.01, settle_cycles=0)
    except SimulationError as exc:
        return [f"simulation: the nominal mechanism does not run: {' '.join(str(exc).split())}"
                f"{_first_unit_slip(config)}"]
    except (ValueError, ArithmeticError) as exc:  # the start: journals preloaded by their contact law, assembled
        moduli = ", ".join(f"clearance_joints.{cj.name}.{side}.youngs_modulus = "
                           f"{getattr(cj, side).youngs_modulus:.3g} Pa" for cj in config.clearance_joints
                           for side in ("bearing_material", "journal_material"))
        slips = unit_slip_warnings(config)
        look = (f"{slips[0]}" if slips else
                f"look first at the clearance joints' radii and materials ({moduli})")
        return [f"simulation: the nominal mechanism does not start ({exc}); the journals start pressed into their "
                f"bores by their contact law, so {look}"]
    return []
