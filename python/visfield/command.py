"""The `visfield` command of a pip-installed package: runs the program installed beside the module."""

import os
import sys
from pathlib import Path


def main() -> None:
    """Replaces this process with the package's `visfield` program, passing the arguments on."""
    program = Path(__file__).resolve().parent / "bin" / "visfield"
    if not os.access(program, os.X_OK):
        sys.exit(f"visfield: error: the program {program} is missing; reinstall the package")
    os.execv(program, [str(program), *sys.argv[1:]])


if __name__ == "__main__":
    main()
