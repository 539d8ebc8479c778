"""The report's glossary: one plain sentence for each term of the trade the page uses, for a reader who did not run
the study. A term is listed only when the page uses it (its triggers, case-sensitive, are looked for in the page's
text), so a study without a validation is not told what the paired verdicts mean."""

from __future__ import annotations

import re

from .markup import e

__all__ = ["TERMS", "glossary_section", "used_terms"]

#: (term, the words on the page that use it, what it means); in the order a reader meets them
TERMS: tuple[tuple[str, tuple[str, ...], str], ...] = (
    ("true model, model call", ("true-model", "model call"),
     "one run of the whole wear model (the clearance joint's dynamics and Archard wear, block by block, to the end "
     "of the history) for one sample of the random inputs; its result is that sample's wear life N_f."),
    ("uniform mode, profile mode", ("uniform mode", "profile mode", "geometry_mode"),
     "how the wear changes the joint's geometry: uniform mode grows the clearance evenly by the deepest wear; "
     "profile mode keeps the worn bore's shape and lets the contact follow it (docs/wear.md)."),
    ("conformity", ("conformity",),
     "the worn arc's half-width over the contact patch's on the unworn bore. At most 1 the journal still touches a "
     "narrow patch and uniform mode is fair; above 1 it sits in its own pocket, the pressure spreads and uniform "
     "mode's depths are too deep (docs/wear.md)."),
    ("limit state, wear life N_f", ("Limit state", "N_f"),
     "G = ln N_f(x) \u2212 ln N: a sample fails at N cycles when its wear life N_f, the cycles at which its judged "
     "wear reaches the allowance, is below N. R(N) is the share of the population that has not failed."),
    ("surrogate, Kriging", ("surrogate", "Kriging"),
     "the smooth model of ln N_f over the random inputs that the study fits to its true-model calls (a Kriging, "
     "i.e. Gaussian-process regression); R(N) is read off it on a large Monte Carlo population instead of running "
     "the true model on every sample."),
    ("design points", ("design points",),
     "the samples the true model was run at; the surrogate is fitted to them."),
    ("Monte Carlo population, n_mc", ("n_mc", "Monte Carlo population"),
     "the random samples of the inputs (n_mc of them) on which the surrogate is read to count failures."),
    ("COV of Pf", ("COV of Pf",),
     "the coefficient of variation of the Monte Carlo estimate of the failure probability Pf = 1 \u2212 R: its "
     "standard error over its value, set by the population's size."),
    ("pf_floor", ("pf_floor",),
     "below this failure probability the population's COV target is not enforced (reliability.pf_floor): a tiny Pf "
     "would need a huge population."),
    ("ESC", ("ESC",),
     "the error-based stopping criterion (Wang and Shafieezadeh 2019): a bound on how much the population's samples "
     "that the surrogate may put on the wrong side of failure can move Pf. The learning stops when it is within its "
     "tolerance (docs/reliability.md)."),
    ("posterior spread", ("posterior spread",),
     "how much R(N) moves over curves drawn from the Kriging's own uncertainty (its posterior): the part of the "
     "surrogate's error that ESC's count misses. The surrogate error of R is the larger of the two."),
    ("hold_iterations, max_calls", ("hold_iterations", "max_calls"),
     "reliability.hold_iterations: on how many successive designs (the design points after each batch of calls) "
     "the stopping rule must hold before the learning stops; reliability.max_calls: the budget of true-model calls. "
     "A learning that spends its budget first has not converged."),
    ("nugget, scatter of a call's life", ("nugget", "call-to-call scatter", "scatter of a call's life"),
     "the Kriging's noise term: the part of each call's ln N_f that the inputs do not explain, fitted from the calls. "
     "It holds the chaotic contact's scatter from one wear history to another, part of which can be the sampling "
     "noise of the few cycles each wear block records (wear.record_cycles); R(N) counts it as part of each "
     "mechanism's life."),
    ("Q\u00b2", ("Q\u00b2", "Q^2"),
     "the leave-one-out predictive R\u00b2 of the surrogate: 1 minus the squared errors of predicting each design "
     "point from the others, over the points' variance of ln N_f. 1 is a perfect prediction; below 0.5 the inputs "
     "explain less than they leave unexplained."),
    ("95 % interval of the life", ("95 % interval",),
     "where the 95 % band of R(N), the Monte Carlo error plus the surrogate's error estimate, crosses the target: "
     "the error of reading the life off this surrogate, not of the wear model's assumptions (docs/study.md, \"How "
     "far to trust the life\")."),
    ("Sobol' indices S1, ST", ("Sobol'",),
     "the share of the variance of the wear that one input explains alone (S1) or with all its interactions (ST)."),
    ("elasticity", ("elasticity",),
     "the relative change of R for a relative change of an input's mean, at the nominal point: (\u03bc / R) "
     "dR/d\u03bc."),
    ("\u2248 in a ranking", ("\u2248",),
     "the two neighbours' changes of R differ by less than the surrogate's error estimate of them: the study does "
     "not tell their order."),
    ("Clopper-Pearson interval", ("Clopper-Pearson",),
     "the exact binomial 95 % interval of a share counted on a finite number of samples."),
    ("inside, reaches it, exceeds it", ("reaches it", "EXCEEDS it", "exceeds it"),
     "the validation's paired verdicts at a level: the 95 % interval of the surrogate's difference from the true "
     "model on the same samples lies inside \u00b1 the surrogate's error estimate (the estimate holds), only "
     "overlaps it (not refuted, not shown) or lies beyond it (the surrogate errs by more than it says)."),
)


def used_terms(text: str) -> list[tuple[str, str]]:
    """(term, meaning) of the :data:`TERMS` whose triggers occur in ``text`` (the page's text, markup removed)."""
    return [(term, meaning) for term, triggers, meaning in TERMS if any(t in text for t in triggers)]


def glossary_section(html_body: str) -> str:
    """The glossary of the terms the page's HTML ``html_body`` uses, as a definition list ('' when it uses none)."""
    import html as _html

    text = _html.unescape(re.sub(r"<[^>]+>", " ", html_body))
    terms = used_terms(text)
    if not terms:
        return ""
    return "<dl class=\"glossary\">" + "".join(f"<dt>{e(term)}</dt><dd>{e(meaning)}</dd>"
                                               for term, meaning in terms) + "</dl>"
