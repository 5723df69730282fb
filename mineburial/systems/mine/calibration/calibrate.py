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

from mineburial._version import __version__
from mineburial.ensembles.runner import Progress, check_threads
from mineburial.errors import ScenarioError
from mineburial.io.files import atomic_write_bytes, atomic_write_text
from mineburial.systems.mine import figures
from mineburial.systems.mine.calibration import cases, conditioning, priors

#: sets a block: the resume granularity
BLOCK = 32
#: equally weighted sets the posterior file holds (at most as many as were drawn): each block's
#: weights resampled to this many keep every set within 1/1024 of its weight; an ensemble draws
#: among 32 of them (posterior.ENSEMBLE_SETS)
SHIPPED_SETS = 1024
METHOD = (
    "importance sampling from the prior: scrambled Sobol' draws of the coefficients and nuisance "
    "parameters, weighted by the product of the evidence rows' scores (Gaussian with measurement "
    "sigma and model discrepancy for continuous rows, 1 - error_rate / error_rate for patterns), "
    "block by block (the impact phase's cases and the scour stage's read disjoint coefficients, so "
    "their posteriors are independent); the shipped sets are each block's weighted sets resampled "
    "systematically to 1,024 equally weighted sets, the blocks paired by a seeded "
    "permutation"
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


def block_of(path: str) -> str:
    """The block of the evidence a coefficient or nuisance parameter belongs to: its case's
    (:data:`cases.CASE_BLOCK`, for a nuisance parameter ``case.name``) or its coefficient's."""
    head = path.split(".")[0]
    return cases.CASE_BLOCK[head] if head in cases.CASE_BLOCK else cases.coefficient_block(path)


def _weights_of(block_w: dict, path: str, n: int) -> np.ndarray:
    """The weights a coefficient's or nuisance parameter's marginal is read under: its block's
    (the prior's where no evidence reads the block)."""
    return block_w.get(block_of(path), np.full(n, 1.0 / n))


def model_choice(prior, coefficients, draws, w) -> dict:
    """The evidence's weight on each label of the model choice ``prior`` (e.g. the scour stage's
    burial law) under its block's weights ``w``: per label its prior and posterior probability,
    the number of prior sets drawn with it, the effective sample size of those sets' weights
    (Kish's, renormalised within the label: how many sets the label's posterior rests on), and
    the posterior of the block's other numeric coefficients among the label's sets."""
    labels = np.asarray(draws[prior.path])
    block = cases.coefficient_block(prior.path)
    mates = [q for q in coefficients if not q.categorical and cases.coefficient_block(q.path) == block]
    out = {}
    for label, p0 in zip(prior.distribution.values, prior.distribution.weights):
        m = labels == label
        mass = float(np.sum(w[m]))
        entry = {
            "prior": float(p0),
            "prior_sets": int(m.sum()),
            "posterior": mass,
            "ess": conditioning.effective_sample_size(w[m]) if mass > 0 else 0.0,
            "coefficients": {},
        }
        if mass > 0:
            wl = np.where(m, w, 0.0) / mass
            entry["coefficients"] = {q.path: conditioning.marginal(q, draws[q.path], wl) for q in mates}
        out[label] = entry
    return out


def condition(coefficients, nuisance, rows, draws, simulated, seed: int) -> tuple[dict, dict, dict]:
    """Per block of the evidence (:data:`cases.CASE_BLOCK`), the (sets,) log likelihood and
    weights of the sets, and the report: effective sample sizes, prior and posterior
    marginals, the influence of each row and the leave-one-out predictive checks.

    The blocks read disjoint coefficients, so the posterior is the product of the blocks'
    and each is weighted on its own: weighting the sets by every row at once would multiply
    the blocks' importance-sampling losses (an effective sample size of about the product of
    their fractions) for nothing."""
    scores = conditioning.log_scores(rows, simulated)  # (sets, rows, grid)
    row_cases = [r.case for r in rows]
    by_case = conditioning.case_log_likelihoods(scores, row_cases)
    n, g = simulated.shape[0], simulated.shape[2]
    blocks = list(dict.fromkeys(cases.CASE_BLOCK[c] for c in by_case))
    block_ll = {
        b: sum((v for c, v in by_case.items() if cases.CASE_BLOCK[c] == b), np.zeros(n)) for b in blocks
    }
    block_w = {b: conditioning.normalised(ll) for b, ll in block_ll.items()}
    w_prior = np.full(n, 1.0 / n)
    drawn = (*coefficients, *(p for p in nuisance if not p.integrate))
    ess_blocks = {b: conditioning.effective_sample_size(w) for b, w in block_w.items()}
    report = {
        "ess": min(ess_blocks.values()),
        "ess_blocks": ess_blocks,
        "n_sets": n,
        "failed_sets": {
            r.id: int(np.sum(~np.isfinite(simulated[:, j]).all(axis=1))) for j, r in enumerate(rows)
        },
        "prior": {p.path: conditioning.marginal(p, draws[p.path], w_prior) for p in drawn},
        "posterior": {
            p.path: conditioning.marginal(p, draws[p.path], _weights_of(block_w, p.path, n)) for p in drawn
        },
        "influence": {},
        "predictive": [],
        "choices": {
            p.path: model_choice(p, coefficients, draws, _weights_of(block_w, p.path, n))
            for p in coefficients
            if p.categorical
        },
    }

    def others(case):
        """(sets,) log likelihood of the other cases of ``case``'s block."""
        block = cases.CASE_BLOCK[case]
        return sum((v for c, v in by_case.items() if c != case and cases.CASE_BLOCK[c] == block), np.zeros(n))

    for p in nuisance:
        if p.integrate:
            case = p.path.split(".")[0]
            joint = np.exp(others(case)[:, None] + scores[:, [c == case for c in row_cases], :].sum(axis=1))
            report["prior"][p.path] = _grid_marginal(p, np.ones((1, g)))
            report["posterior"][p.path] = _grid_marginal(p, joint)
    for j, r in enumerate(rows):
        alone = conditioning.normalised(conditioning.log_mean_exp(scores[:, j, :], axis=1))
        report["influence"][r.id] = {
            p.path: conditioning.influence(p, draws[p.path], alone, w_prior) for p in drawn
        }
        # every other row of its block: the other cases' likelihoods and this case's other rows,
        # point by point (a row of another block reads other coefficients: no information)
        rest = others(r.case)
        mates = [k for k, c in enumerate(row_cases) if c == r.case and k != j]
        joint = rest[:, None] + scores[:, mates, :].sum(axis=1)
        w_joint = conditioning.normalised(joint.ravel())
        chk = conditioning.predictive_check(r, simulated[:, j, :].ravel(), w_joint, seed + j)
        # the posterior predictive with every row (the fit, not a check): this case's rows point by point
        every = rest[:, None] + scores[:, [c == r.case for c in row_cases], :].sum(axis=1)
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
    return block_ll, block_w, report


def posterior_record(coefficients, draws, block_ll, block_w, report, identity) -> dict:
    """The shipped posterior: :data:`SHIPPED_SETS` equally weighted sets, each block's
    coefficients from that block's weighted sets resampled systematically (the first block in
    order, the others permuted with the seed, so that the blocks are paired independently), and
    the provenance. A block with no evidence is resampled from its prior draws with equal weights."""
    n = len(next(iter(draws.values())))
    for b, w in block_w.items():
        if not np.any(w > 0):
            raise ScenarioError(
                f"calibration: no coefficient set reproduces the {b} evidence (every weight is 0)"
            )
    blocks = list(dict.fromkeys([*block_w, *(cases.coefficient_block(p.path) for p in coefficients)]))
    rng = np.random.default_rng(identity["seed"])
    m = min(n, SHIPPED_SETS)
    index = {}
    for k, b in enumerate(blocks):
        idx = conditioning.systematic_resample(block_w.get(b, np.full(n, 1.0 / n)), m)
        index[b] = idx if k == 0 else idx[rng.permutation(m)]
    members = {b: [p.path for p in coefficients if cases.coefficient_block(p.path) == b] for b in blocks}
    where = [index[cases.coefficient_block(p.path)] for p in coefficients]
    return {
        "format": "mineburial-posterior",
        "format_version": 2,
        **identity,
        "created": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
        "method": METHOD,
        "coefficients": [p.path for p in coefficients],
        "labels": {p.path: list(p.distribution.values) for p in coefficients if p.categorical},
        "sets": [[_scalar(draws[p.path][w[k]]) for p, w in zip(coefficients, where)] for k in range(m)],
        "weights": [1.0 / m] * m,
        "blocks": members,
        # block by block, each shipped set's place among the prior draws and its log likelihood
        "set_index": {b: index[b].tolist() for b in blocks},
        "log_likelihood": {b: block_ll[b][index[b]].tolist() for b in blocks if b in block_ll},
        "distinct_sets": {b: int(np.unique(index[b]).size) for b in blocks},
        "ess": report["ess"],
        "ess_blocks": report["ess_blocks"],
        "report": report,
    }


@dataclasses.dataclass
class Calibration:
    """A finished calibration: the posterior record written, and of every prior set its draws
    (path -> values), weight and log likelihood."""

    record: dict
    draws: dict
    weights: dict  # block -> (sets,)
    log_likelihood: dict  # block -> (sets,)

    def weights_of(self, path: str) -> np.ndarray:
        """The weights of the prior sets under which ``path``'s marginal is read (its block's)."""
        return _weights_of(self.weights, path, len(next(iter(self.draws.values()))))


def identity(n: int, seed: int, priors_file, evidence_file) -> dict:
    return {
        "priors_sha256": priors.file_digest(priors_file),
        "evidence_sha256": priors.file_digest(evidence_file),
        "n_prior_sets": int(n),
        "seed": int(seed),
        "mineburial_version": __version__,
        # 2: each block's priors from a Sobol' sequence of their own (conditioning.draw_sets)
        "draws": 2,
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
    draws = conditioning.draw_sets((*coefficients, *nuisance), n, seed, block_of)
    blocks = _Blocks(output, ident)
    if threads is None:
        threads = numba.get_num_threads()
    simulated = simulate(rows, coefficients, nuisance, draws, n, threads, blocks, progress)
    block_ll, block_w, report = condition(coefficients, nuisance, rows, draws, simulated, seed)
    record = posterior_record(coefficients, draws, block_ll, block_w, report, ident)
    atomic_write_text(output, json.dumps(record, indent=1, allow_nan=True) + "\n")
    blocks.remove()
    return Calibration(record, draws, block_w, block_ll)


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


def _choice_lines(choices: dict) -> list[str]:
    """The report's section on each model choice with a prior: the evidence's weight on each
    label, and the block's coefficients among the sets of each label."""
    if not choices:
        return []
    lines = [
        "",
        "## Model choices: the evidence's weight on each label",
        "",
        "Each label's prior and posterior probability, the prior sets drawn with it, and the "
        "effective sample size of their weights (Kish's, within the label: the sets its posterior "
        "rests on). A law whose sets are weighted down by the evidence has a small posterior "
        "probability; an ensemble that names it draws the coefficients of its own sets "
        "(docs/calibration.md).",
    ]
    for path, labels in choices.items():
        lines += [
            "",
            f"### {path}",
            "",
            "| label | prior | posterior | prior sets | ESS within |",
            "|---|---|---|---|---|",
        ]
        for label, e in labels.items():
            lines.append(
                f"| {label} | {e['prior']:.3f} | {e['posterior']:.3f} | {e['prior_sets']} | {e['ess']:.1f} |"
            )
        coefs = list(dict.fromkeys(q for e in labels.values() for q in e["coefficients"]))
        if coefs:
            lines += [
                "",
                "Posterior of the block's coefficients among the sets of each label (median [5 %, 95 %]):",
                "",
                "| coefficient | " + " | ".join(labels) + " |",
                "|---|" + "---|" * len(labels),
            ]
            for q in coefs:
                cells = (
                    _fmt(e["coefficients"][q]) if q in e["coefficients"] else "-" for e in labels.values()
                )
                lines.append(f"| {q} | " + " | ".join(cells) + " |")
    return lines


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
        "Effective sample size of each block of the evidence (conditioned on its own: the blocks "
        "read disjoint coefficients): "
        + "; ".join(
            f"{b} {e:.1f} of {rep['n_sets']} sets ({record['distinct_sets'][b]} distinct among the "
            f"{len(record['weights'])} shipped)"
            for b, e in rep["ess_blocks"].items()
        )
        + ".",
        "",
        "## Prior and posterior (median [5 %, 95 %]; a model choice: its probabilities)",
        "",
        "| coefficient | prior | posterior |",
        "|---|---|---|",
    ]
    for path, post in rep["posterior"].items():
        lines.append(f"| {path} | {_fmt(rep['prior'][path])} | {_fmt(post)} |")
    lines += _choice_lines(rep.get("choices", {}))
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


def plot_marginals(record: dict, coefficients, draws, weights_of, path) -> None:
    """Prior (grey) against posterior (blue) marginals of every coefficient, one panel each
    (``weights_of(path)``: the prior sets' weights for that coefficient, its block's)."""
    Figure = figures.figure_class()
    k = len(coefficients)
    cols = 3
    rows = math.ceil(k / cols)
    fig = Figure(figsize=(4.0 * cols, 2.8 * rows), layout="constrained")
    axes = fig.subplots(rows, cols, squeeze=False).ravel()
    for ax, prior in zip(axes, coefficients):
        values = draws[prior.path]
        weights = weights_of(prior.path)
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
    ess = ", ".join(f"{b} {e:.0f}" for b, e in rep["ess_blocks"].items())
    fig.suptitle(f"mineburial calibrate: {rep['n_sets']} prior sets, effective sample size {ess}")
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
        plot_marginals(record, coefficients, cal.draws, cal.weights_of, args.plot)
    rep = record["report"]
    passed = sum(c["passed"] for c in rep["predictive"])
    print(
        f"calibrate: {rep['n_sets']} sets, effective sample size "
        + ", ".join(f"{b} {e:.1f}" for b, e in rep["ess_blocks"].items())
        + "; predictive checks "
        f"{passed} of {len(rep['predictive'])} pass; {time.perf_counter() - t0:.1f} s"
    )
    for path, post in rep["posterior"].items():
        print(f"  {path}: prior {_fmt(rep['prior'][path])} -> posterior {_fmt(post)}")
    for path, labels in rep.get("choices", {}).items():
        print(
            f"  {path}, effective sample size within each label: "
            + ", ".join(f"{k} {e['ess']:.1f} of {e['prior_sets']}" for k, e in labels.items())
        )
    print(
        f"wrote {output}"
        + (f", {args.report}" if args.report else "")
        + (f", {args.plot}" if args.plot else "")
    )
    return 0
