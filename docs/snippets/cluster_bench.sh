python "$REPO/benchmarks/bench_cluster.py"
