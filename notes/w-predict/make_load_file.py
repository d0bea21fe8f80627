"""Write the 300 000-row CSV file that load.py reads (campaign B's bounces repeated, as bench_load.py does)."""
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from benchmarks.bench_load import write_file  # noqa: E402

write_file(Path("/tmp/bouncelab_load_bench.csv"), 300_000)
