"""`python -m fuzz` (with `tools/` on the path: `make fuzz`)."""

from fuzz import main

raise SystemExit(main())
