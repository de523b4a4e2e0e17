import sys

from uma.cli import main

sys.exit(main())
