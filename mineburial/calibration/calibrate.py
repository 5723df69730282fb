"""``mineburial calibrate``: draw coefficient sets from the priors, run every evidence case
under each, score them and write the posterior (issue 32; docs/calibration.md).

The evidence drops of a block of sets run on a thread pool (the compiled drop releases the
GIL); each finished block is kept in ``<output>.partial/`` (written atomically), so an
interrupted calibration resumes where it stopped when the same command is run again. The
blocks are keyed by what decides them (the priors' and evidence's SHA-256, the number of
sets, the seed and the version); a folder left by another calibration is refused.
"""

from __future__ import annotations

import concurrent.futures
import dataclasses
import datetime
import io
import json
import math
import pathlib
import time

import numba
import numpy as np

from mineburial import figures
from mineburial._version import __version__
from mineburial.calibration import cases, conditioning, priors
from mineburial.ensembles.runner import Progress, check_threads
from mineburial.errors import ScenarioError
from mineburial.io.files import atomic_write_bytes, atomic_write_text

#: sets a block: the resume granularity
BLOCK = 32
#: sets whose weight is below this fraction of the largest are not shipped
WEIGHT_FLOOR = 1e-6
METHOD = (
    "importance sampling from the prior: scrambled Sobol' draws of the coefficients and nuisance "
    "parameters, weighted by the product of the evidence rows' scores (Gaussian with measurement "
    "sigma and model discrepancy for continuous rows, 1 - error_rate / error_rate for patterns)"
)


def _experiments(rows) -> list[tuple[str, str]]:
    """The distinct (case, variant) drops the rows need, in row order."""
    out = []
    for r in rows:
        if (r.case, r.variant) not in out:
            out.append((r.case, r.variant))
    return out


def grid_size(nuisance) -> int:
    """The number of points of the integrated nuisance parameters (1 without any); every
    integrated parameter has the same (one grid axis for all cases), at most one a case."""
    sizes = {p.integrate for p in nuisance if p.integrate}
    cases_with = [p.path.split(".")[0] for p in nuisance if p.integrate]
    if len(sizes) > 1 or len(set(cases_with)) != len(cases_with):
        raise ScenarioError(
            "evidence: integrated nuisance parameters must all have the same number of points, "
            "at most one a case"
        )
    return sizes.pop() if sizes else 1


def _one_set(rows, nuisance, coefficient_paths, draws, s, g) -> np.ndarray:
    """The simulated quantity of every row under set ``s`` at each of the ``g`` grid points,
    (rows, g) (NaN where the drop gave none)."""
    coeffs = {p: _scalar(draws[p][s]) for p in coefficient_paths}
    out = np.full((len(rows), g), np.nan)
    for case, variant in _experiments(rows):
        mine = [pr for pr in nuisance if pr.path.split(".")[0] == case]
        drawn = {pr.path.split(".", 1)[1]: float(draws[pr.path][s]) for pr in mine if not pr.integrate}
        grid = {pr.path.split(".", 1)[1]: pr.grid() for pr in mine if pr.integrate}
        got = cases.run_case(case, variant, drawn, grid, coeffs)[1]
        for j, r in enumerate(rows):
            if (r.case, r.variant) == (case, variant) and r.quantity in got:
                out[j] = got[r.quantity]  # one value (no grid) fills every point
    return out


def _scalar(v):
    return str(v) if isinstance(v, (str, np.str_)) else float(v)


class _Blocks:
    """The finished blocks of one calibration in ``<output>.partial/``."""

    def __init__(self, output: pathlib.Path, identity: dict):
        self.folder = output.with_name(output.name + ".partial")
        self.identity = identity
        tag = self.folder / "identity.json"
        if self.folder.exists():
            try:
                old = json.loads(tag.read_text())
            except (OSError, ValueError):
                old = None
            if old != identity:
                raise ScenarioError(
                    f"{self.folder} holds the blocks of another calibration (other priors, evidence, "
                    "number of sets, seed or version): remove it or choose another output"
                )
        else:
            self.folder.mkdir(mode=0o700)
            atomic_write_text(tag, json.dumps(identity, sort_keys=True))

    def path(self, start: int) -> pathlib.Path:
        return self.folder / f"sets_{start:07d}.npy"

    def load(self, start: int, shape) -> np.ndarray | None:
        try:
            arr = np.load(self.path(start), allow_pickle=False)
        except (OSError, ValueError):
            return None
        return arr if arr.shape == shape else None

    def save(self, start: int, arr: np.ndarray) -> None:
        buf = io.BytesIO()
        np.save(buf, arr, allow_pickle=False)
        atomic_write_bytes(self.path(start), buf.getvalue())

    def remove(self) -> None:
        for f in self.folder.iterdir():
            f.unlink()
        self.folder.rmdir()


def simulate(rows, coefficients, nuisance, draws, n, threads, blocks=None, progress=None) -> np.ndarray:
    """(n, rows, grid) simulated quantities of every set, block by block (resumed from
    ``blocks``)."""
    paths = [p.path for p in coefficients]
    g = grid_size(nuisance)
    out = np.full((n, len(rows), g), np.nan)
    with concurrent.futures.ThreadPoolExecutor(max_workers=threads) as pool:
        for start in range(0, n, BLOCK):
            stop = min(start + BLOCK, n)
            done = blocks.load(start, (stop - start, len(rows), g)) if blocks else None
            if done is None:
                sets = range(start, stop)
                done = np.array(list(pool.map(lambda s: _one_set(rows, nuisance, paths, draws, s, g), sets)))
                if blocks:
                    blocks.save(start, done)
            out[start:stop] = done
            if progress:
                progress(stop, n)
    return out


def _grid_marginal(prior, joint_w) -> dict:
    """Median and 5-95 % of an integrated nuisance parameter under (sets, grid) weights."""
    lo, med, hi = conditioning.weighted_quantile(prior.grid(), joint_w.sum(axis=0), [0.05, 0.5, 0.95])
    return {"median": float(med), "q05": float(lo), "q95": float(hi)}


def condition(coefficients, nuisance, rows, draws, simulated, seed: int) -> tuple[np.ndarray, dict]:
    """Weights of the sets, and the report: effective sample size, prior and posterior
    marginals, the influence of each row and the leave-one-out predictive checks."""
    scores = conditioning.log_scores(rows, simulated)  # (sets, rows, grid)
    row_cases = [r.case for r in rows]
    by_case = conditioning.case_log_likelihoods(scores, row_cases)
    log_likelihood = sum(by_case.values())
    w = conditioning.normalised(log_likelihood)
    n, g = simulated.shape[0], simulated.shape[2]
    w_prior = np.full(n, 1.0 / n)
    drawn = (*coefficients, *(p for p in nuisance if not p.integrate))
    report = {
        "ess": conditioning.effective_sample_size(w),
        "n_sets": n,
        "failed_sets": {
            r.id: int(np.sum(~np.isfinite(simulated[:, j]).all(axis=1))) for j, r in enumerate(rows)
        },
        "prior": {p.path: conditioning.marginal(p, draws[p.path], w_prior) for p in drawn},
        "posterior": {p.path: conditioning.marginal(p, draws[p.path], w) for p in drawn},
        "influence": {},
        "predictive": [],
    }
    for p in nuisance:
        if p.integrate:
            case = p.path.split(".")[0]
            rest = sum(v for c, v in by_case.items() if c != case)
            joint = np.exp(
                np.asarray(rest)[:, None] + scores[:, [c == case for c in row_cases], :].sum(axis=1)
            )
            report["prior"][p.path] = _grid_marginal(p, np.ones((1, g)))
            report["posterior"][p.path] = _grid_marginal(p, joint)
    for j, r in enumerate(rows):
        alone = conditioning.normalised(conditioning.log_mean_exp(scores[:, j, :], axis=1))
        report["influence"][r.id] = {
            p.path: conditioning.influence(p, draws[p.path], alone, w_prior) for p in drawn
        }
        # every other row: the other cases' likelihoods and this case's other rows, point by point
        rest = sum(v for c, v in by_case.items() if c != r.case)
        mates = [k for k, c in enumerate(row_cases) if c == r.case and k != j]
        joint = np.asarray(rest)[:, None] + scores[:, mates, :].sum(axis=1)
        w_joint = conditioning.normalised(joint.ravel())
        chk = conditioning.predictive_check(r, simulated[:, j, :].ravel(), w_joint, seed + j)
        # the posterior predictive with every row (the fit, not a check): this case's rows point by point
        every = np.asarray(rest)[:, None] + scores[:, [c == r.case for c in row_cases], :].sum(axis=1)
        fit = conditioning.predictive_check(
            r, simulated[:, j, :].ravel(), conditioning.normalised(every.ravel()), seed + j
        )
        report["predictive"].append(
            {
                "id": r.id,
                "observed": r.observed,
                "ess_without": conditioning.effective_sample_size(w_joint.reshape(n, g).sum(axis=1)),
                "lower": chk.lower,
                "upper": chk.upper,
                "probability": chk.probability,
                "passed": chk.passed,
                "posterior_lower": fit.lower,
                "posterior_upper": fit.upper,
                "posterior_probability": fit.probability,
            }
        )
    return log_likelihood, w, report


def posterior_record(coefficients, draws, log_likelihood, w, report, identity) -> dict:
    """The shipped posterior: the sets with weight above :data:`WEIGHT_FLOOR` of the largest,
    their weights (renormalised) and the provenance."""
    if not np.any(w > 0):
        raise ScenarioError("calibration: no coefficient set reproduces the evidence (every weight is 0)")
    keep = np.flatnonzero(w >= WEIGHT_FLOOR * w.max())
    kept = w[keep] / w[keep].sum()
    return {
        "format": "mineburial-posterior",
        "format_version": 1,
        **identity,
        "created": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "method": METHOD,
        "coefficients": [p.path for p in coefficients],
        "labels": {p.path: list(p.distribution.values) for p in coefficients if p.categorical},
        "sets": [[_scalar(draws[p.path][s]) for p in coefficients] for s in keep],
        "weights": kept.tolist(),
        "set_index": keep.tolist(),  # each kept set's place among the prior draws
        "log_likelihood": log_likelihood[keep].tolist(),
        "ess": report["ess"],
        "ess_kept": conditioning.effective_sample_size(kept),
        "report": report,
    }


@dataclasses.dataclass
class Calibration:
    """A finished calibration: the posterior record written, and of every prior set its draws
    (path -> values), weight and log likelihood."""

    record: dict
    draws: dict
    weights: np.ndarray
    log_likelihood: np.ndarray


def identity(n: int, seed: int, priors_file, evidence_file) -> dict:
    return {
        "priors_sha256": priors.file_digest(priors_file),
        "evidence_sha256": priors.file_digest(evidence_file),
        "n_prior_sets": int(n),
        "seed": int(seed),
        "mineburial_version": __version__,
    }


def calibrate(
    output,
    n: int = 512,
    seed: int = 20261128,
    threads: int | None = None,
    priors_file=priors.PRIORS_FILE,
    evidence_file=priors.EVIDENCE_FILE,
    progress=None,
) -> Calibration:
    """Run a calibration and write its posterior to ``output`` (JSON)."""
    if not (isinstance(n, int) and n >= 2):
        raise ScenarioError(
            f"calibrate: -n {n} must be an integer >= 2 (coefficient sets drawn from the prior)"
        )
    output = pathlib.Path(output)
    coefficients = priors.load_priors(priors_file)
    rows, nuisance = priors.load_evidence(evidence_file)
    ident = identity(n, seed, priors_file, evidence_file)
    draws = conditioning.draw_sets((*coefficients, *nuisance), n, seed)
    blocks = _Blocks(output, ident)
    if threads is None:
        threads = numba.get_num_threads()
    simulated = simulate(rows, coefficients, nuisance, draws, n, threads, blocks, progress)
    log_likelihood, w, report = condition(coefficients, nuisance, rows, draws, simulated, seed)
    record = posterior_record(coefficients, draws, log_likelihood, w, report, ident)
    atomic_write_text(output, json.dumps(record, indent=1, allow_nan=True) + "\n")
    blocks.remove()
    return Calibration(record, draws, w, log_likelihood)


def _progress_lines(total: int):
    """The run driver's rate-limited progress lines, counting sets."""
    bar = Progress(total, unit="sets")
    return lambda done, n: bar.update(done, final=done == n)


# ---------------------------------------------------------------------------
# report, figure and command line
# ---------------------------------------------------------------------------
def _fmt(m: dict) -> str:
    if "median" in m:
        return f"{m['median']:.3g} [{m['q05']:.3g}, {m['q95']:.3g}]"
    return ", ".join(f"{k} {v:.2f}" for k, v in m.items())


def report_text(record: dict) -> str:
    """The calibration report (Markdown): prior against posterior of every coefficient, the
    effective sample size, which rows move which coefficient, the predictive checks."""
    rep = record["report"]
    lines = [
        "# Calibration report",
        "",
        f"Built {record['created']} by mineburial {record['mineburial_version']} from {rep['n_sets']} "
        f"coefficient sets drawn from the prior (seed {record['seed']}); priors SHA-256 "
        f"{record['priors_sha256'][:12]}, evidence SHA-256 {record['evidence_sha256'][:12]}.",
        "",
        f"Method: {record['method']}.",
        "",
        f"Effective sample size: {rep['ess']:.1f} of {rep['n_sets']} sets; "
        f"{len(record['weights'])} sets kept "
        f"(weight >= {WEIGHT_FLOOR:g} of the largest; effective {record['ess_kept']:.1f}).",
        "",
        "## Prior and posterior (median [5 %, 95 %]; a model choice: its probabilities)",
        "",
        "| coefficient | prior | posterior |",
        "|---|---|---|",
    ]
    for path, post in rep["posterior"].items():
        lines.append(f"| {path} | {_fmt(rep['prior'][path])} | {_fmt(post)} |")
    paths = list(rep["posterior"])
    lines += [
        "",
        "## Which row moves which coefficient",
        "",
        "Total-variation distance between the prior and the weights of each row alone "
        "(0: not moved, 1: disjoint; on 10 prior-quantile bins of a number). With few sets a row's "
        "weights are noisy: values below ~0.1 are not resolved.",
        "",
        "| row | " + " | ".join(paths) + " |",
        "|---|" + "---|" * len(paths),
    ]
    for rid, inf in rep["influence"].items():
        cells = (f"{inf[p]:.2f}" if p in inf else "-" for p in paths)
        lines.append(f"| {rid} | " + " | ".join(cells) + " |")
    lines += [
        "",
        "## Leave-one-out predictive checks",
        "",
        "Each row left out, the others' weights predict it: a measurement passes inside the 5-95 % "
        "predictive band; a pattern passes when the model gives it with a predictive probability of "
        "at least 10 %.",
        "",
        "| row | observed | predicted without it | ESS without | result | posterior predictive (every row) |",
        "|---|---|---|---|---|---|",
    ]
    for chk in rep["predictive"]:
        pred = (
            f"P = {chk['probability']:.2f}"
            if math.isfinite(chk["probability"])
            else f"[{chk['lower']:.3g}, {chk['upper']:.3g}]"
        )
        result = "pass" if chk["passed"] else "FAIL"
        fit = (
            f"P = {chk['posterior_probability']:.2f}"
            if math.isfinite(chk["posterior_probability"])
            else f"[{chk['posterior_lower']:.3g}, {chk['posterior_upper']:.3g}]"
        )
        lines.append(
            f"| {chk['id']} | {chk['observed']:g} | {pred} | {chk['ess_without']:.1f} | {result} | {fit} |"
        )
    failed = {k: v for k, v in rep["failed_sets"].items() if v}
    if failed:
        lines += [
            "",
            "Sets whose evidence drop gave no value (scored 0): "
            + ", ".join(f"{k} {v}" for k, v in failed.items()),
        ]
    return "\n".join(lines) + "\n"


def plot_marginals(record: dict, coefficients, draws, weights, path) -> None:
    """Prior (grey) against posterior (blue) marginals of every coefficient, one panel each."""
    Figure = figures.figure_class()
    k = len(coefficients)
    cols = 3
    rows = math.ceil(k / cols)
    fig = Figure(figsize=(4.0 * cols, 2.8 * rows), layout="constrained")
    axes = fig.subplots(rows, cols, squeeze=False).ravel()
    for ax, prior in zip(axes, coefficients):
        values = draws[prior.path]
        if prior.categorical:
            labels = list(prior.distribution.values)
            x = np.arange(len(labels))
            pri = [np.mean(values == lab) for lab in labels]
            post = [float(np.sum(weights[values == lab])) for lab in labels]
            ax.bar(x - 0.2, pri, 0.4, color="0.7", label="prior")
            ax.bar(x + 0.2, post, 0.4, color="tab:blue", label="posterior")
            ax.set_xticks(x, labels)
            ax.set_ylabel("probability")
        else:
            v = values.astype(np.float64)
            bins = np.linspace(v.min(), v.max(), 21)
            ax.hist(v, bins=bins, density=True, color="0.7", label="prior")
            ax.hist(
                v,
                bins=bins,
                weights=weights,
                density=True,
                histtype="step",
                lw=2,
                color="tab:blue",
                label="posterior",
            )
            ax.set_ylabel("density")
        ax.set_title(prior.path, fontsize=9)
    for ax in axes[k:]:
        ax.set_visible(False)
    axes[0].legend(fontsize=8)
    rep = record["report"]
    fig.suptitle(f"mineburial calibrate: {rep['n_sets']} prior sets, effective sample size {rep['ess']:.0f}")
    figures.save_figure(fig, path, dpi=110)


def run_cli(args) -> int:
    """``mineburial calibrate``."""
    threads = check_threads(args.threads, "--threads")
    output = pathlib.Path(args.output)
    if args.plot:
        figures.check_plot_path(args.plot, output, what="the posterior")
    t0 = time.perf_counter()
    coefficients = priors.load_priors()
    progress = None if args.quiet else _progress_lines(args.sets)
    cal = calibrate(output, n=args.sets, seed=args.seed, threads=threads, progress=progress)
    record = cal.record
    if args.report:
        atomic_write_text(args.report, report_text(record))
    if args.plot:
        plot_marginals(record, coefficients, cal.draws, cal.weights, args.plot)
    rep = record["report"]
    passed = sum(c["passed"] for c in rep["predictive"])
    print(
        f"calibrate: {rep['n_sets']} sets, effective sample size {rep['ess']:.1f}; predictive checks "
        f"{passed} of {len(rep['predictive'])} pass; {time.perf_counter() - t0:.1f} s"
    )
    for path, post in rep["posterior"].items():
        print(f"  {path}: prior {_fmt(rep['prior'][path])} -> posterior {_fmt(post)}")
    print(
        f"wrote {output}"
        + (f", {args.report}" if args.report else "")
        + (f", {args.plot}" if args.plot else "")
    )
    return 0
