"""Which crates the README's two commands would compile twice.

`cargo run --release -p prehensile-cli -- demo` and then `cargo test --workspace --release`
share every compiled dependency only when cargo resolves each to the same features in both
builds; the CLI's manifest asks for the features the tests' dependencies turn on (see the
comment there). This lists every dependency unit of the demo's build that the tests' build
does not reuse, with the features each build wants. Prints nothing and exits 0 when all are
shared. Run from the repository root (it runs both builds, so the first time it compiles
everything):
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
    demo = units(["cargo", "build", "--release", "-p", "prehensile-cli"])
    tests = units(["cargo", "test", "--workspace", "--release", "--no-run"])
    unshared = sorted(demo - tests)
    for name, kind, features in unshared:
        wanted = [f for n, k, f in tests if (n, k) == (name, kind)]
        print(f"{name} ({kind}): the demo builds {list(features)}, the tests {wanted}")
    sys.exit(1 if unshared else 0)


if __name__ == "__main__":
    main()
