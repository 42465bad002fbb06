"""The paper's reported figures (normalized RMSE, mean of 20 runs) and its benchmark setup."""

#: [E_train, E_test, E_Ttest] as reported, by method name.
REPORTED = {
    "fuzzy_bell4": (0.0224, 0.0241, 0.0075),
    "elm_standard": (0.0232, 0.0233, 0.0072),
    "elm_enlarged": (0.0210, 0.0234, 0.0070),
    "elm_enlarged_regularized": (0.0231, 0.0234, 0.0074),
    "elm_conditioned": (0.0231, 0.0235, 0.0076),
}

#: The headline configurations of the paper's ELM models (section 4-5).
HEADLINE_ELMS = {
    "elm_standard": dict(n_hidden=6, scheme="standard", solver="pinv"),
    "elm_regularized": dict(n_hidden=6, scheme="standard", solver="ridge", C=1e5),
    "elm_enlarged": dict(n_hidden=10, scheme="enlarged", solver="pinv"),
    "elm_enlarged_regularized": dict(n_hidden=10, scheme="enlarged", solver="ridge", C=1e5),
}

#: Number of runs the paper averages over.
SEEDS = 20

#: Other figures the paper states: ||beta|| bounds (section 5) and its fuzzy choice (section 3).
REPORTED_BETA_BOUND = {"elm_enlarged_regularized": 6.0, "elm_conditioned": 17.0}
FUZZY_MFS = 4

#: Table 2 of the paper: grades (accuracy, generalization, training time, conditioning).
TABLE2 = {
    "fuzzy_bell4": ("sufficient", "poor", "moderate", "good"),
    "elm_standard": ("sufficient", "moderate", "short", "bad"),
    "elm_regularized": ("poor", "poor", "short", "good if accuracy is sacrificed"),
    "elm_enlarged": ("good", "good", "short", "good"),
    "elm_enlarged_regularized": ("good", "the best", "short", "the best"),
    "elm_conditioned": ("good", "good", "long", "good"),
}

#: The paper's qualitative findings that ``fricgen reproduce`` checks, by key.
CLAIMS = {
    "anfis_overfits": "ANFIS: training error falls and test error rises as MFs grow (fig. 2-3, 8)",
    "standard_ill_conditioned": "standard ELM: cond(H^T H) and ||beta|| become very big as M grows (fig. 10)",
    "activation_irrelevant": "sigmoid, sine and RBF activations give similar errors (fig. 13)",
    "regularization_spoils_accuracy": "C = 1e5 alone degrades the standard ELM's accuracy (fig. 15)",
    "enlarged_well_conditioned": "enlarged variability lowers ||beta|| and cond versus standard (fig. 16-18)",
    "enlarged_regularized_small_beta": "enlarged + C = 1e5 keeps ||beta|| < 6 and no overfitting for M < 50 (fig. 20)",
    "conditioned_beta_below_17": "half OPT by PSO: mean ||beta|| < 17 for any M (fig. 22)",
    "elm_matches_fuzzy": "the headline ELMs and the 4-MF fuzzy model reach comparable errors (sections 3-5)",
}
