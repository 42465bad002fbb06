"""PNG figures of ``fricgen reproduce``, mirroring the paper's figures 1-22 (needs matplotlib).

Sweep figures plot the seed means of ``results.json``; curve figures (fits over the data,
activation functions, membership functions, the conditioning landscape of fig. 21) refit the
headline models on seed 0.
"""
from __future__ import annotations

from typing import Dict

import numpy as np

from .._plot import png, pyplot
from ..data import synthesize_benchmark
from ..fit.elm import EnlargedScheme, log10_cond
from ..friction import preset
from ..networks.elm import hidden_matrix

#: The files ``write_figures`` produces, with the paper figures they mirror.
FIGURES = {
    "friction_data.png": "figs. 1-2: the 3-source friction and the normalized data",
    "anfis_errors.png": "figs. 3, 8: ANFIS errors versus number of bell / Gaussian MFs",
    "anfis_model.png": "figs. 5, 7: the 4-MF fuzzy model over the data and its trained MFs",
    "elm_errors.png": "figs. 9, 15, 16, 20, 22: ELM errors versus number of neurons",
    "elm_activations.png": "fig. 13: standard ELM errors for sigmoid, sine and RBF activations",
    "elm_beta_cond.png": "fig. 10: mean ||beta|| and log10 cond(H^T H) versus neurons",
    "cond_grid.png": "fig. 14: log10 cond(1/C I + H^T H) over neurons x C",
    "fitted_curves.png": "figs. 11, 17, 19: headline models over the training data (seed 0)",
    "activation_functions.png": "figs. 12, 18: hidden-unit outputs of trained models (seed 0)",
    "pso_landscape.png": "fig. 21: log10 cond(H^T H) as a function of the 11th neuron's w, b",
}


def _errors_panel(ax, grid, curve, title, xlabel="number of hidden neurons"):
    for key, style in (("e_train", "-"), ("e_test", "--"), ("e_ttest", ":")):
        ax.plot(grid, curve[key], style, label=key.replace("e_", "E_").replace("ttest", "Ttest"))
    ax.set_title(title, fontsize=9)
    ax.set_xlabel(xlabel)
    ax.set_yscale("log")
    ax.legend(fontsize=7)


def render_figures(result: dict, fitted: Dict[str, object]) -> Dict[str, bytes]:
    """Every figure of ``FIGURES`` as PNG bytes, by file name (matplotlib needed).

    Parameters
    ----------
    result : dict
        A ``reproduce`` result (its ``sweeps`` and ``benchmark``).
    fitted : dict
        Headline method names -> estimators fitted on seed 0 (``fitted_seed0``).

    Returns
    -------
    dict
        File name -> PNG bytes.

    Examples
    --------
    A result takes minutes (``reproduce``); the figures it gives are these:

    >>> from fricgen.paper import FIGURES, fitted_seed0, render_figures, reproduce
    >>> len(FIGURES), FIGURES["pso_landscape.png"].split(":")[0]
    (10, 'fig. 21')
    >>> pngs = render_figures(reproduce(seeds=2, quick=True), fitted_seed0())  # doctest: +SKIP
    """
    plt = pyplot()
    shape = result["benchmark"].get("shape", "gauss")
    bench = synthesize_benchmark(preset("paper3", shape), seed=0)
    d = bench.dataset
    sw = result["sweeps"]
    written = {}

    def save(fig, name):
        fig.tight_layout()
        written[name] = png(fig, dpi=90)

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    v = np.linspace(-0.08, 0.08, 801)
    axes[0].plot(v, bench.friction(v), "k")
    axes[0].set(xlabel="v (m/s)", ylabel="F (N)", title="3-source friction (Table 1)")
    x_test, t_test = d.targets(bench.test.v, bench.test.f)
    axes[1].plot(d.x, d.t, ".", ms=3, label="training")
    axes[1].plot(x_test, t_test, "x", ms=3, label="test")
    axes[1].set(xlabel="x = K_in v", ylabel="t = K_out (F - B v)", title="normalized data (seed 0)")
    axes[1].legend(fontsize=7)
    save(fig, "friction_data.png")

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for ax, mf in zip(axes, ("bell", "gauss")):
        _errors_panel(ax, sw["anfis"]["grid"], sw["anfis"]["variants"][mf], f"ANFIS, {mf} MFs",
                      "number of membership functions")
    save(fig, "anfis_errors.png")

    fz = fitted["fuzzy_bell4"]
    xs = np.linspace(0, 1, 400)
    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    axes[0].plot(d.x, d.t, ".", ms=3, color="0.6", label="training data")
    axes[0].plot(xs, fz.predict(xs), "r", label="fuzzy, 4 bell MFs")
    axes[0].legend(fontsize=7)
    axes[0].set(xlabel="x", title="fuzzy model over the data")
    axes[1].plot(xs, fz.network_.memberships(xs))
    axes[1].set(xlabel="x", ylabel="membership", title="trained bell MFs")
    save(fig, "anfis_model.png")

    names = [("standard_sigmoid", "standard ELM"), ("regularized", "standard, C = 1e5"),
             ("enlarged", "enlarged variability"), ("enlarged_regularized", "enlarged, C = 1e5")]
    fig, axes = plt.subplots(1, 5, figsize=(18, 3.8), sharey=True)
    grid = sw["neurons"]["grid"]
    for ax, (key, title) in zip(axes, names):
        _errors_panel(ax, grid, sw["neurons"]["variants"][key], title)
    _errors_panel(axes[4], sw["conditioned"]["grid"], sw["conditioned"], "half OPT by PSO")
    save(fig, "elm_errors.png")

    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8), sharey=True)
    for ax, act in zip(axes, ("sigmoid", "sine", "rbf")):
        _errors_panel(ax, grid, sw["neurons"]["variants"][f"standard_{act}"], f"standard ELM, {act}")
    save(fig, "elm_activations.png")

    fig, axes = plt.subplots(1, 2, figsize=(10, 3.8))
    for key, title in names:
        curve = sw["neurons"]["variants"][key]
        axes[0].plot(grid, curve["beta_norm"], label=title)
        axes[1].plot(grid, curve["log10_cond"], label=title)
    axes[0].plot(sw["conditioned"]["grid"], sw["conditioned"]["beta_norm"], "k--", label="half OPT")
    axes[1].plot(sw["conditioned"]["grid"], sw["conditioned"]["log10_cond"], "k--", label="half OPT")
    axes[0].set(yscale="log", xlabel="number of hidden neurons", title="mean ||beta||")
    axes[1].set(xlabel="number of hidden neurons", title="mean log10 cond(H^T H)")
    axes[0].legend(fontsize=7)
    save(fig, "elm_beta_cond.png")

    cg = sw["cond_grid"]
    fig, ax = plt.subplots(figsize=(6, 4.2))
    img = ax.imshow(np.array(cg["log10_cond"]), aspect="auto", origin="lower", cmap="viridis")
    ax.set_xticks(range(len(cg["C"])), [f"{np.log10(c):.0f}" for c in cg["C"]])
    ax.set_yticks(range(len(cg["neurons"])), [str(n) for n in cg["neurons"]])
    ax.set(xlabel="log10 C", ylabel="neurons", title="log10 cond(1/C I + H^T H), standard ELM")
    fig.colorbar(img, ax=ax)
    save(fig, "cond_grid.png")

    show = ["elm_standard", "elm_enlarged", "elm_enlarged_regularized", "elm_conditioned",
            "default", "oracle"]
    fig, axes = plt.subplots(2, 3, figsize=(13, 7), sharex=True, sharey=True)
    x_th, t_th = d.targets(bench.theory.v, bench.theory.f)
    for ax, name in zip(axes.ravel(), show):
        ax.plot(d.x, d.t, ".", ms=2, color="0.6")
        ax.plot(x_th, t_th, "k", lw=0.8, label="true")
        ax.plot(xs, fitted[name].predict(xs), "r", label=name)
        ax.set_title(name, fontsize=9)
        ax.legend(fontsize=7)
    save(fig, "fitted_curves.png")

    fig, axes = plt.subplots(1, 3, figsize=(14, 3.8))
    for ax, name in zip(axes, ("elm_standard", "elm_enlarged", "elm_auto")):
        ax.plot(xs, fitted[name].network_.hidden(xs), lw=0.8)
        ax.set(xlabel="x", title=f"activation functions, {name} (M = {fitted[name].network_.n_hidden})")
    save(fig, "activation_functions.png")

    rng = np.random.default_rng(0)
    w, b = EnlargedScheme().draw(10, rng)
    H10 = hidden_matrix("sigmoid", d.x, w, b)
    ww, bb = np.meshgrid(np.linspace(-10, 10, 61), np.linspace(-10, 10, 61))
    H = np.concatenate([np.broadcast_to(H10, (ww.size,) + H10.shape),
                        hidden_matrix("sigmoid", d.x, ww.ravel(), bb.ravel()).T[:, :, None]], axis=2)
    s = np.linalg.svd(H, compute_uv=False)
    z = np.array([log10_cond(si, n_hidden=11) for si in s]).reshape(ww.shape)
    fig, ax = plt.subplots(figsize=(6, 4.2))
    img = ax.contourf(ww, bb, z, 30, cmap="viridis")
    fig.colorbar(img, ax=ax)
    ax.set(xlabel="w_11", ylabel="b_11", title="log10 cond(H^T H), 10 RAND + neuron 11")
    save(fig, "pso_landscape.png")
    return written
