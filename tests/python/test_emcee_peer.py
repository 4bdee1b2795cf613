"""bench/peers/emcee_peer.py's bulk ESS: the known answer on AR(1) chains, and emcee's own on a Gaussian."""

import importlib.util
import os

import numpy as np
import pytest

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
_spec = importlib.util.spec_from_file_location("emcee_peer", os.path.join(ROOT, "bench", "peers", "emcee_peer.py"))
peer = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(peer)


def ar1(phi, chains, n, seed):
    rng = np.random.default_rng(seed)
    x = np.empty((chains, n))
    x[:, 0] = rng.standard_normal(chains) / np.sqrt(1 - phi * phi)
    e = rng.standard_normal((chains, n))
    for t in range(1, n):
        x[:, t] = phi * x[:, t - 1] + e[:, t]
    return x


@pytest.mark.parametrize("phi", [0.0, 0.5, 0.9])
def test_bulk_ess_of_ar1_chains_is_n_over_tau(phi):
    # An AR(1) chain's integrated autocorrelation time is (1 + φ) / (1 − φ).
    x = ar1(phi, 4, 5000, seed=1)
    expected = x.size * (1 - phi) / (1 + phi)
    assert peer.bulk_ess(x) == pytest.approx(expected, rel=0.15)
    # Rank normalisation makes it blind to a monotone transform.
    assert peer.bulk_ess(np.exp(x)) == pytest.approx(peer.bulk_ess(x), rel=1e-9)


def test_stuck_chains_have_little_ess_and_large_rhat():
    x = ar1(0.5, 4, 2000, seed=2) + np.arange(4)[:, None] * 5.0
    assert peer.bulk_ess(x) < 50
    assert peer.rank_normalised_rhat(x) > 1.5
    assert peer.rank_normalised_rhat(ar1(0.5, 4, 2000, seed=3)) < 1.01


def test_emcee_on_a_gaussian_agrees_with_its_own_autocorrelation_time():
    emcee = pytest.importorskip("emcee")
    cov = np.array([[1.0, 0.9], [0.9, 1.0]])
    precision = np.linalg.inv(cov)
    sampler = emcee.EnsembleSampler(16, 2, lambda x: -0.5 * np.einsum("ki,ij,kj->k", x, precision, x),
                                    vectorize=True)
    sampler._random = np.random.mtrand.RandomState(1)
    sampler.run_mcmc(np.random.default_rng(1).normal(0, 0.1, (16, 2)), 3000, progress=False)
    kept = sampler.get_chain(discard=1000)  # steps × walkers × 2
    for j in range(2):
        ess = peer.bulk_ess(kept[:, :, j].T)
        # emcee's τ is per walker over the ensemble's mean autocorrelation: the same quantity.
        tau = emcee.autocorr.integrated_time(kept[:, :, j][:, :, None], quiet=True)[0]
        assert ess == pytest.approx(kept[:, :, j].size / tau, rel=0.35)
        assert abs(kept[:, :, j].mean()) < 0.1
