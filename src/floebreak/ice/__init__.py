"""Ice: material laws, observations, thickness sampling and floe fields."""
