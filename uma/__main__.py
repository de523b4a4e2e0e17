import sys

from uma.interrupt import exit_at_once

exit_at_once()  # Ctrl-C while the command line is still being imported: one line, exit 130
from uma.cli import main  # noqa: E402

sys.exit(main())
