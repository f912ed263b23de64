"""Which crates the README's commands would compile twice.

`cargo run --release -p prehensile-cli -- demo`, `cargo test --workspace --release` and the
Python package's `pip install ./crates/prehensile-python` (maturin builds `prehensile-python`
alone, with pyo3's `extension-module` feature) share every compiled dependency only when cargo
resolves each to the same features in all three builds; the CLI and the Python package depend
on `prehensile-workspace-hack`, which asks for the features the tests' dependencies turn on
(see its manifest). This lists every dependency unit of the demo's or the Python package's
build that the tests' build compiles with other features, with the features each build wants.
Crates only the Python package uses (pyo3, numpy) are its own to build. Prints nothing and
exits 0 when all are shared. Run from the repository root (it runs the builds, so the first
time it compiles everything):
    python3 tools/build/shared_units.py
"""
import json
import subprocess
import sys


def units(command):
    """(crate@version, target kind, features) of every dependency unit the cargo command builds."""
    out = subprocess.run(command + ["--message-format=json"], capture_output=True, text=True,
                         check=True).stdout
    found = set()
    for line in out.splitlines():
        try:
            message = json.loads(line)
        except json.JSONDecodeError:
            continue
        package = message.get("package_id", "")
        if message.get("reason") == "compiler-artifact" and "path+file" not in package:
            # The package id names the version: a crate can be built in two versions (syn 2, 3).
            name_version = package.rsplit("#", 1)[-1]
            found.add((name_version, message["target"]["kind"][0],
                       tuple(sorted(message["features"]))))
    return found


def main():
    tests = units(["cargo", "test", "--workspace", "--release", "--no-run"])
    built_by_tests = {(name, kind) for name, kind, _ in tests}
    unshared = []
    for label, command in [
        ("the demo", ["cargo", "build", "--release", "-p", "prehensile-cli"]),
        ("the Python package", ["cargo", "build", "--release", "-p", "prehensile-python",
                                "--features", "pyo3/extension-module"]),
    ]:
        for name, kind, features in sorted(units(command) - tests):
            if (name, kind) in built_by_tests:
                unshared.append((label, name, kind, features))
    for label, name, kind, features in unshared:
        wanted = [f for n, k, f in tests if (n, k) == (name, kind)]
        print(f"{name} ({kind}): {label} builds {list(features)}, the tests {wanted}")
    sys.exit(1 if unshared else 0)


if __name__ == "__main__":
    main()
