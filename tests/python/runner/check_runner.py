"""What run_pytest.py tells ctest: passed (0) when every test passed, skipped (77) when one was
skipped and none failed, failed (1) when one failed, whatever else was skipped."""
import pathlib
import subprocess
import sys

HERE = pathlib.Path(__file__).resolve().parent
RUNNER = HERE.parent / "run_pytest.py"

expected = {"passes.py": 0, "passes_and_skips.py": 77, "fails_and_skips.py": 1}
wrong = []
for name, code in expected.items():
    got = subprocess.run([sys.executable, str(RUNNER), str(HERE / name)], capture_output=True,
                         text=True)
    if got.returncode != code:
        wrong.append(f"{name}: exit {got.returncode}, expected {code}\n{got.stdout}{got.stderr}")
print("\n".join(wrong) or "run_pytest.py: 0, 77 and 1 as expected")
sys.exit(1 if wrong else 0)
