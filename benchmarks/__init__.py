"""Measured claims: ``python -m benchmarks NAME [--quick] --json PATH``."""
