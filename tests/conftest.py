"""Shared test set-up: every test runs with the repository's packages importable."""
