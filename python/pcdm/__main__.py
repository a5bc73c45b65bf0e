"""``python -m pcdm [options] input.poly``: the sequential mesher ``./mesh`` -- the same
options (``python -m pcdm --help``), messages, output files and exit status."""

import sys
from typing import List, Optional

from . import _core


def main(argv: Optional[List[str]] = None) -> int:
    args = sys.argv[1:] if argv is None else list(argv)
    sys.stdout.flush()
    sys.stderr.flush()
    return _core.main(["python -m pcdm"] + args)


if __name__ == "__main__":
    sys.exit(main())
