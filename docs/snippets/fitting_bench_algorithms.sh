cd "$REPO"
date -u "+%Y-%m-%d %H:%M UTC"
python benchmarks/bench_algorithms.py
