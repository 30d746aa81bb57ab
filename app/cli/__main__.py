"""`python -m app.cli ...` is the `hri-lab` command."""

from app.cli.main import main

raise SystemExit(main())
