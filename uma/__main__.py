import sys

try:
    from uma.cli import main
except KeyboardInterrupt:  # Ctrl-C while the command line is still being imported
    sys.stderr.write("uma: interrupted\n")
    sys.exit(130)

sys.exit(main())
