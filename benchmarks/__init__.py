"""parcover's benchmarks: ``python -m benchmarks [--quick]`` writes ``reports/benchmarks.md``."""
