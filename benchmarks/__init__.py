"""The benchmark suite: ``python -m benchmarks`` runs it (`benchmarks.__main__`), each benchmark a
script (``python benchmarks/bench_simulation.py ...``) that writes JSON and PNG to ``results/``;
`benchmarks.status` reads the open issues' goals from those files. Tests import these modules as
``benchmarks.<name>`` (the repository root is on pytest's path)."""
