"""The paper's one-at-a-time reliability sensitivity (Section 6.2.3, Figs. 22-24).

Each variable's mean is moved to a fraction of its nominal value (80 % and 120 % in the paper), the others held at
their nominal distributions, and the reliability recomputed. How a law is moved depends on its family
(:func:`shifted_marginal`):

* a positive law whose support starts at zero (scipy's standard support [0, inf): the lognormal, gamma and
  two-parameter Weibull the config builds, with loc = 0) is scaled, X -> factor x X: shape and coefficient of
  variation kept, the standard deviation scaled with the mean, the support still starting at 0. Moving its loc
  instead would put the support's lower end at (1 - factor) x mean below zero at factor < 1 (a negative wear
  coefficient or hardness, which the model cannot take);
* any other law (normal, Gumbel, uniform, truncated normal, beta) is translated by (factor - 1) x mean: shape and
  standard deviation kept, bounds (a uniform's or beta's ends, a truncated normal's truncation points) moving with
  it.
The reliability function is supplied by the caller (in a wear study: the Kriging surrogate re-used and,
where the shifted population leaves the design's region, enriched by active learning).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field


def _shape_loc_scale(marginal) -> tuple[tuple, float, float]:
    """(shapes, loc, scale) of a frozen scipy.stats distribution from its public ``args``/``kwds`` and the
    shape names in ``dist.shapes`` (the order scipy's own argument parsing uses: shapes, loc, scale)."""
    dist = marginal.dist
    names = [n.strip() for n in dist.shapes.split(",")] if dist.shapes else []
    args, kwds = list(marginal.args), dict(marginal.kwds)
    shapes = tuple(args[i] if i < len(args) else kwds[n] for i, n in enumerate(names))
    rest = args[len(names):]
    loc = rest[0] if len(rest) > 0 else kwds.get("loc", 0.0)
    scale = rest[1] if len(rest) > 1 else kwds.get("scale", 1.0)
    return shapes, loc, scale


def scales_with_mean(marginal) -> bool:
    """Whether :func:`shifted_marginal` scales ``marginal`` (X -> factor x X) rather than translating it: its family's
    standard support is [0, inf) (lognorm, gamma, weibull_min, expon, ...)."""
    dist = marginal.dist
    return float(dist.a) == 0.0 and float(dist.b) == float("inf")


def shifted_marginal(marginal, factor: float):
    """The marginal with its mean multiplied by ``factor`` and its shape kept.

    * Positive families whose standard support is [0, inf) (:func:`scales_with_mean`: the config's lognormal, gamma
      and Weibull) are scaled, X -> factor x X: loc and scale both multiplied by ``factor``, so the coefficient of
      variation is kept, the standard deviation scales with the mean and the support's lower end stays at
      factor x loc (0 for the config's laws, built with loc = 0). Translating them instead would move that end to
      (1 - factor) x mean below zero at factor < 1: with a 40 % COV, a x0.8 shift puts 0.1 % (gamma) to 1 % (Weibull)
      of the samples at negative values, which the model cannot take. A law of such a family given with loc != 0
      (the config builds none) is scaled all the same: its mean is still multiplied by ``factor`` exactly, its COV
      kept, and a lower end >= 0 stays >= 0.
    * Every other family (normal, Gumbel, uniform, truncated normal, beta) is translated by (factor - 1) x mean:
      shape and standard deviation kept; its bounds (a uniform's or beta's ends, a truncated normal's truncation
      points) move with it.
    """
    dist = marginal.dist
    shapes, loc, scale = _shape_loc_scale(marginal)
    if scales_with_mean(marginal):
        return dist(*shapes, loc=loc * factor, scale=scale * factor)
    return dist(*shapes, loc=loc + (factor - 1.0) * marginal.mean(), scale=scale)


@dataclass
class MeanShiftResult:
    names: list[str]
    labels: list[str]
    factors: tuple[float, float]
    reliability_nominal: float
    reliability_low: list[float]
    reliability_high: list[float]
    extra_calls: list[int] = field(default_factory=list)

    def swings(self) -> list[float]:
        """Per variable, the largest absolute change of reliability of its two shifts."""
        return [max(abs(lo - self.reliability_nominal), abs(hi - self.reliability_nominal))
                for lo, hi in zip(self.reliability_low, self.reliability_high)]

    def ranking(self) -> list[str]:
        """Variables ordered by the largest absolute change of reliability."""
        return [n for _, n in sorted(zip(self.swings(), self.names), key=lambda t: -t[0])]


def unresolved_pairs(ranking: Sequence[str], swing: dict[str, float], error: dict[str, float],
                     groups: dict[str, Sequence[str]]) -> list[dict]:
    """Neighbours in a group's ranking whose order the study does not resolve: the difference of their swings is
    no larger than the sum of the error estimates of the two reliabilities that set those swings (each the
    surrogate's 95 % bound: ESC's or the Kriging posterior's, the larger). ``ranking``: all variables, largest
    swing first; ``groups``: group -> member names."""
    out = []
    for group, members in groups.items():
        ordered = [n for n in ranking if n in set(members)]
        for a, b in zip(ordered, ordered[1:]):
            diff = swing[a] - swing[b]
            bound = error[a] + error[b]
            if diff <= bound:  # equal swings are no order, even with exact reliabilities
                out.append({"group": group, "first": a, "second": b, "swing_difference": float(diff),
                            "error_sum": float(bound)})
    return out


def mean_shift_table(reliability_of: Callable[[list], tuple[float, int]], marginals: Sequence,
                     names: Sequence[str], labels: Sequence[str] | None = None,
                     factors: tuple[float, float] = (0.8, 1.2),
                     reliability_nominal: float | None = None) -> MeanShiftResult:
    """Reliability with each mean shifted to ``factors`` x nominal, one variable at a time.

    ``reliability_of(marginals) -> (R, n_new_model_calls)``.
    """
    marginals = list(marginals)
    if reliability_nominal is None:
        reliability_nominal, _ = reliability_of(marginals)
    lows, highs, calls = [], [], []
    for i in range(len(marginals)):
        row = []
        n_calls = 0
        for factor in factors:
            shifted = list(marginals)
            shifted[i] = shifted_marginal(marginals[i], factor)
            r, k = reliability_of(shifted)
            row.append(float(r))
            n_calls += int(k)
        lows.append(row[0])
        highs.append(row[1])
        calls.append(n_calls)
    return MeanShiftResult(list(names), list(labels or names), tuple(factors), float(reliability_nominal),
                           lows, highs, calls)
