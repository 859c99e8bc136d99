"""``python -m bemcontact``: the ``bemcontact`` command."""

import sys

from .cli import main

sys.exit(main())
