#!/usr/bin/python3
"""emcee on vkrecon's own likelihood: bulk ESS per 1,000 evaluations beside `vkrecon run`'s.

Synthesises photographs of an asset at its truth, samples its posterior (the scene's priors ×
the likelihood through `import vkrecon`) with emcee's ensemble, and prints one markdown row
per move set, with the same figure bench/sampler.sh takes from map.json: the smallest
rank-normalised split bulk ESS over the parameters × 1000 / every likelihood evaluation.
With --run, `vkrecon run` on the same photographs adds its row first; with --match-run emcee then
samples what run's chains sample, the log-likelihood at run's calibrated σ divided by its κ
(bench/peers_notes.md).

    PYTHONPATH=build/python nice /usr/bin/python3 bench/peers/emcee_peer.py --scale 0.5 --run
"""

import argparse
import glob
import json
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


# --- bulk ESS, as optimiser/Statistics.cpp computes it (Vehtari et al. 2021) -------------

def _inverse_normal_cdf(p):
    # numpy has no Φ⁻¹; NormalDist's (Wichura's AS241) and the C++'s (Acklam's, one Halley
    # step) are both accurate to double precision.
    from statistics import NormalDist
    return np.vectorize(NormalDist().inv_cdf)(p)


def rank_normalise(chains):
    """Normal scores of the pooled ranks (ties averaged), Blom's offsets; chains is M × N."""
    chains = np.asarray(chains, dtype=float)
    flat = chains.ravel()
    order = np.argsort(flat, kind="stable")
    ranks = np.empty(flat.size)
    ranks[order] = np.arange(1, flat.size + 1)
    # Ties get their average rank, as the C++ does.
    values, inverse = np.unique(flat, return_inverse=True)
    if values.size < flat.size:
        ranks = (np.bincount(inverse, ranks) / np.bincount(inverse))[inverse]
    return _inverse_normal_cdf((ranks - 0.375) / (flat.size + 0.25)).reshape(chains.shape)


def effective_sample_size(chains):
    """ESS of M × N chains: Geyer's initial monotone sequence over the chains' mean autocorrelation."""
    chains = np.asarray(chains, dtype=float)
    m, n = chains.shape
    if n < 4:
        return math.nan
    means = chains.mean(axis=1)
    w = chains.var(axis=1, ddof=1).mean()
    var_plus = w * (n - 1) / n + (means.var(ddof=1) if m > 1 else 0.0)
    if not (var_plus > 0.0 and math.isfinite(var_plus)):
        return math.nan
    centred = chains - means[:, None]
    # Autocovariance of every lag at once (biased, 1/n), averaged over chains.
    f = np.fft.rfft(centred, n=2 * n, axis=1)
    acov = np.fft.irfft(f * np.conj(f), axis=1)[:, :n].mean(axis=0) / n
    rho = 1.0 - (w - acov) / var_plus
    r = np.zeros(n + 1)
    even, odd = 1.0, rho[1]
    r[0], r[1] = even, odd
    s = 1
    while s + 4 < n and even + odd > 0.0:
        even, odd = rho[s + 1], rho[s + 2]
        if even + odd >= 0.0:
            r[s + 1], r[s + 2] = even, odd
        s += 2
    max_s = s
    if even > 0.0:
        r[max_s + 1] = even
    for k in range(1, max_s - 2, 2):
        if r[k + 1] + r[k + 2] > r[k - 1] + r[k]:
            r[k + 1] = r[k + 2] = 0.5 * (r[k - 1] + r[k])
    tau = -1.0 + r[max_s + 1] + 2.0 * r[:max_s].sum()
    total = m * n
    return min(total / tau, total * math.log10(total))


def bulk_ess(chains):
    """Rank-normalised split bulk ESS of M × N chains of one parameter (NaN below 8 draws)."""
    chains = np.asarray(chains, dtype=float)
    n = chains.shape[1]
    if n < 8:
        return math.nan
    z = rank_normalise(chains)
    half = n // 2
    return effective_sample_size(np.concatenate([z[:, :half], z[:, n - half:]]))


def split_rhat(chains):
    chains = np.asarray(chains, dtype=float)
    n = chains.shape[1] // 2
    halves = np.concatenate([chains[:, :n], chains[:, chains.shape[1] - n:]])
    w = halves.var(axis=1, ddof=1).mean()
    return math.sqrt(((n - 1) / n * w + halves.mean(axis=1).var(ddof=1)) / w)


def rank_normalised_rhat(chains):
    """The larger of the bulk and the folded (tail) rank-normalised split R-hat."""
    chains = np.asarray(chains, dtype=float)
    folded = np.abs(chains - np.median(chains))
    return max(split_rhat(rank_normalise(chains)), split_rhat(rank_normalise(folded)))


# --- the posterior ------------------------------------------------------------------------

def log_prior_terms(scene_json, names):
    """(lo, hi, mean, sd) per parameter, from the scene file's priors and bounds.

    The module does not expose the prior, so this reads the scene file's: uniform, or normal
    with optional bounds (docs/guide/SCENE_FORMAT.md). Constant expressions are not handled.
    """
    lo, hi, mean, sd = (np.empty(len(names)) for _ in range(4))
    for i, name in enumerate(names):
        p = scene_json["parameters"][name]
        if "uniform" in p["prior"]:
            lo[i], hi[i] = map(float, p["prior"]["uniform"])
            mean[i], sd[i] = 0.0, math.inf
        else:
            mean[i], sd[i] = map(float, p["prior"]["normal"])
            lo[i], hi[i] = -math.inf, math.inf
        if "bounds" in p:
            lo[i], hi[i] = max(lo[i], float(p["bounds"][0])), min(hi[i], float(p["bounds"][1]))
    return lo, hi, mean, sd


class Posterior:
    """Vectorised log posterior for emcee; counts every likelihood evaluation."""

    def __init__(self, likelihood, prior, kappa):
        self.likelihood = likelihood
        self.kappa = kappa
        self.lo, self.hi, self.mean, self.sd = prior
        self.evaluations = 0

    def __call__(self, x):
        x = np.atleast_2d(x)
        inside = np.all((x >= self.lo) & (x <= self.hi), axis=1)
        normal = np.isfinite(self.sd)
        lp = np.full(len(x), -np.inf)
        lp[inside] = -0.5 * (((x[inside][:, normal] - self.mean[normal]) / self.sd[normal]) ** 2).sum(axis=1)
        # Outside the support the likelihood is not asked: no render, no evaluation counted.
        rows = np.flatnonzero(inside)
        chunk = self.likelihood.max_batch
        for first in range(0, len(rows), chunk):
            part = rows[first:first + chunk]
            # As recon/LikelihoodTarget.cpp scores for the chains: the total over κ.
            lp[part] += self.likelihood.evaluate(x[part])["total"] / self.kappa
            self.evaluations += len(part)
        return lp


# --- the runs -----------------------------------------------------------------------------

def stripped_scene(asset, seed):
    """The asset's scene without its likelihood and sampler blocks, as bench/sampler.sh runs it."""
    s = json.load(open(os.path.join(ROOT, "assets", asset, "scene.json")))
    s.pop("likelihood", None)
    s.pop("sampler", None)
    s["sampler"] = {"seed": seed}
    return s


def run_emcee(args, scene_json, images, moves_name):
    import emcee
    import vkrecon

    asset_dir = os.path.join(ROOT, "assets", args.asset)
    sets = [f"images={images}", f"cameras={images}/cameras.json", f"likelihood.sigma={args.model_sigma}"]
    scene = vkrecon.scene_from_dict(scene_json, asset_dir, set=sets)
    names = scene.parameter_names
    truth = scene.values_from_file(os.path.join(asset_dir, "truth.json"))
    likelihood = vkrecon.Likelihood(scene, batch=args.batch, level=args.level)
    start = truth if args.start == "truth" else scene.initial_values
    likelihood.calibrate_photometric(start)
    prior = log_prior_terms(scene_json, names)
    posterior = Posterior(likelihood, prior, args.kappa)

    width = np.where(np.isfinite(prior[1] - prior[0]), prior[1] - prior[0], 6 * prior[3])
    rng = np.random.default_rng(args.seed)
    walkers = args.walkers or max(16, 2 * len(names))
    p0 = start + args.ball * width * rng.standard_normal((walkers, len(names)))
    p0 = np.clip(p0, prior[0] + 1e-9 * width, prior[1] - 1e-9 * width)
    moves = None
    if moves_name == "de":
        moves = [(emcee.moves.DEMove(), 0.8), (emcee.moves.DESnookerMove(), 0.2)]
    sampler = emcee.EnsembleSampler(walkers, len(names), posterior, moves=moves, vectorize=True)
    # emcee's own seed, so a row repeats.
    sampler._random = np.random.mtrand.RandomState(args.seed)
    steps = args.evaluations // walkers
    burn = steps // 2
    t0 = time.time()
    state = sampler.run_mcmc(p0, burn, progress=False)
    if args.recalibrate:
        # As `run` refits its colour correction at the mode once it has found it: at the best
        # walker after the burn-in. The walkers' scores are recomputed under it (counted).
        best = sampler.get_chain(flat=True)[np.argmax(sampler.get_log_prob(flat=True))]
        likelihood.calibrate_photometric(best)
        sampler.reset()
        state = emcee.State(state.coords)
    sampler.run_mcmc(state, steps - burn, progress=False)
    wall = time.time() - t0

    chain = sampler.get_chain()  # steps × walkers × P; after reset(), the sampled half only
    kept = chain if args.recalibrate else chain[burn:]
    ess = np.array([bulk_ess(kept[:, :, j].T) for j in range(len(names))])
    mean, sd = kept.reshape(-1, len(names)).mean(axis=0), kept.reshape(-1, len(names)).std(axis=0)
    worst = int(np.nanargmin(ess))
    rhat = max(rank_normalised_rhat(kept[:, :, j].T) for j in range(len(names)))
    return {
        "sampler": f"emcee {emcee.__version__}, " + ("stretch" if moves_name == "stretch" else "DE 0.8 + snooker 0.2")
                   + f", σ {args.model_sigma:g}, κ {args.kappa:g}, from {args.start}",
        "walkers": walkers, "steps": steps, "evaluations": posterior.evaluations, "wall": wall,
        "min_ess": float(ess[worst]), "worst": names[worst],
        "acceptance": float(np.mean(sampler.acceptance_fraction)), "rhat": rhat,
        "z": np.abs(mean - truth) / sd, "error": np.abs(mean - truth) / width, "names": names,
    }


def check_port(out, m):
    """Warns where bulk_ess on the run's posterior draws (chains/) differs from map.json's."""
    draws = []
    for f in sorted(glob.glob(os.path.join(out, "chains", "stan-*.csv"))):
        rows = [line.rstrip("\n").split(",") for line in open(f) if not line.startswith("#")]
        draws.append(dict(zip(rows[0], np.array(rows[1:], dtype=float).T)))
    for name, p in m["parameters"].items():
        ours = bulk_ess(np.stack([d[name] for d in draws])) if draws else math.nan
        if not math.isclose(ours, p["ess"] or math.nan, rel_tol=1e-6):
            print(f"emcee_peer: bulk ESS of {name}: {ours:.3f} here, {p['ess']} in map.json", file=sys.stderr)


def run_vkrecon(args, scene_json, images):
    """`vkrecon run` on the same photographs, with the asset's likelihood and sampler blocks removed."""
    asset_dir = os.path.join(ROOT, "assets", args.asset)
    # Beside the asset's scene, whose textures it names by relative paths.
    fd, path = tempfile.mkstemp(suffix=".json", prefix=".scene_emcee_peer_", dir=asset_dir)
    out = tempfile.mkdtemp(prefix="emcee_peer_run_")
    try:
        with os.fdopen(fd, "w") as f:
            json.dump(scene_json, f)
        t0 = time.time()
        subprocess.run([args.vkrecon, "run", path, "-q", "--set", f"images={images}",
                        "--set", f"cameras={images}/cameras.json", "-o", out],
                       stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, check=False)
        wall = time.time() - t0
        m = json.load(open(os.path.join(out, "map.json")))
        check_port(out, m)
    finally:
        os.remove(path)
        shutil.rmtree(out, ignore_errors=True)
    truth = json.load(open(os.path.join(asset_dir, "truth.json")))
    names = list(m["parameters"])
    z = np.array([abs(m["parameters"][k]["mean"] - truth[k]) / m["parameters"][k]["sd"] for k in names])
    calibration = m["calibration"]
    return {
        "sigma": calibration["sigma"], "kappa": calibration["kappa"],
        "sampler": f"vkrecon run (default; calibrated σ {calibration['sigma']:.3g}, κ {calibration['kappa']:.3g})",
        "walkers": "—", "steps": m["iterations"], "evaluations": m["evaluations"], "wall": wall,
        "min_ess": m["sampling"]["min_ess"] or math.nan, "worst": "—", "acceptance": math.nan,
        "rhat": m["sampling"]["max_rhat"] or math.nan, "z": z, "names": names,
    }


def row(args, r):
    per_1000 = 1000.0 * r["min_ess"] / r["evaluations"]
    z = ", ".join(f"{n} {v:.1f}" for n, v in zip(r["names"], r["z"]))
    acc = "—" if math.isnan(r["acceptance"]) else f"{r['acceptance']:.2f}"
    return (f"| {args.asset} | {args.scale} | {args.seed} | {r['sampler']} | {r['walkers']} | {r['steps']} "
            f"| {r['evaluations']} | {r['wall']:.0f} | {acc} | {r['rhat']:.3f} | {r['min_ess']:.1f} ({r['worst']}) "
            f"| {per_1000:.1f} | {max(r['z']):.1f} | {z} |")


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--asset", default="house")
    ap.add_argument("--sigma", type=float, default=16, help="noise of the synthesised photographs")
    ap.add_argument("--model-sigma", type=float, default=16,
                    help="the likelihood's σ (`run` estimates it at the mode; this is its known value)")
    ap.add_argument("--kappa", type=float, default=1.0,
                    help="divides the log-likelihood, as `run`'s sandwich factor does for its chains")
    ap.add_argument("--match-run", action="store_true",
                    help="with --run: run first, then give emcee its calibrated σ and κ (the chains' target)")
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--scale", type=float, default=0.5, help="photograph size (synth --scale)")
    ap.add_argument("--level", type=int, default=0, help="pyramid level emcee scores at")
    ap.add_argument("--batch", type=int, default=16, help="the likelihood's batch size")
    ap.add_argument("--walkers", type=int, default=0, help="0: max(16, 2 × parameters)")
    ap.add_argument("--evaluations", type=int, default=10000, help="budget per emcee run")
    ap.add_argument("--moves", default="stretch,de",
                    help="comma-separated move sets: stretch (emcee's default), de (DE 0.8 + snooker 0.2)")
    ap.add_argument("--start", choices=["initial", "truth"], default="initial",
                    help="ball centre: the scene's initial values (where `run` starts) or the truth")
    ap.add_argument("--ball", type=float, default=0.01, help="start ball's sd, as a share of each prior width")
    ap.add_argument("--no-recalibrate", dest="recalibrate", action="store_false",
                    help="keep the colour correction fitted at the start")
    ap.add_argument("--run", action="store_true", help="also `vkrecon run` on the same photographs")
    ap.add_argument("--vkrecon", default=os.path.join(ROOT, "build", "apps", "vkrecon"))
    args = ap.parse_args()

    scene_json = stripped_scene(args.asset, args.seed)
    with tempfile.TemporaryDirectory(prefix="emcee_peer_") as work:
        images = os.path.join(work, "images")
        asset_dir = os.path.join(ROOT, "assets", args.asset)
        subprocess.run([args.vkrecon, "synth", os.path.join(asset_dir, "scene.json"), "--at",
                        os.path.join(asset_dir, "truth.json"), "--noise", str(args.sigma), "--seed", str(args.seed),
                        "--scale", str(args.scale), "-q", "-o", images], check=True)
        print("| asset | scale | seed | sampler | walkers | steps | evaluations | wall s | acceptance | max R̂ "
              "| min bulk ESS (parameter) | ESS per 1,000 evaluations | max \\|mean − truth\\|/sd | per parameter |")
        print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
        sys.stdout.flush()
        if args.run:
            r = run_vkrecon(args, scene_json, images)
            print(row(args, r), flush=True)
            if args.match_run:
                args.model_sigma, args.kappa = r["sigma"], r["kappa"]
        for moves in args.moves.split(","):
            print(row(args, run_emcee(args, scene_json, images, moves)), flush=True)


if __name__ == "__main__":
    main()
