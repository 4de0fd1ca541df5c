"""The packaged plant profiles of the simulated axis: their names, their files and the default
(docs/plant.md). Names only: :mod:`.plant` reads the files, and the command line offers the names
without loading it."""

PROFILE_RESOURCES: dict[str, str] = {
    "ideal": "plant_ideal.toml",
    "realistic": "plant_realistic.toml",
    "warm-up": "plant_warm_up.toml",
}
"""the packaged plant file of each profile"""
DEFAULT_PROFILE = "ideal"
DEFAULT_PLANT_RESOURCE = PROFILE_RESOURCES[DEFAULT_PROFILE]
