"""A client for `crates/prehensile-sim/examples/step_timing.rs`: starts it once and asks it for
timings, for the benchmark scripts beside this file."""
import subprocess
import sys


class StepTiming:
    """One step_timing process: `binary [--engine ENGINE] HAND DT...`, then `DT STEPS` lines
    answered with the median microseconds per step of that many steps."""

    def __init__(self, binary: str, hand: str, dts, cwd=None, engine: str = "rapier"):
        self.process = subprocess.Popen(
            [str(binary), "--engine", engine, str(hand)] + [str(dt) for dt in dts],
            cwd=cwd, stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True,
        )
        if self.process.stdout.readline().strip() != "ready":
            sys.exit(f"{binary} did not start (see its error above)")

    def step_us(self, dt: float, steps: int) -> float:
        self.process.stdin.write(f"{dt} {steps}\n")
        self.process.stdin.flush()
        answer = self.process.stdout.readline()
        if not answer:
            sys.exit("step_timing stopped (see its error above)")
        return float(answer)

    def close(self):
        self.process.stdin.close()
        self.process.wait()
