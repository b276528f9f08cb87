from lcefem.validation.commands import MODELS, parallel_if_fe  # noqa: F401  (transitional)
