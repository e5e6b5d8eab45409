"""Runs every benchmark in turn (`make bench`); each writes its table to benchmarks/results/."""
import pathlib
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent
SCRIPTS = ["bench_engine.py", "bench_wide.py", "bench_c.py", "bench_loop.py", "bench_verify.py",
           "bench_arm.py", "bench_c_proofs.py"]

if __name__ == "__main__":
    for script in SCRIPTS:
        print(f"== {script}", flush=True)
        subprocess.run([sys.executable, str(HERE / script)], check=True)
