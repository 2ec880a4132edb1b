"""`python -m floebreak.cli`: the console command without its collector settings (`floebreak.__main__`)."""

from floebreak.cli.main import main

main()
