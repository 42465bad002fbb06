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
