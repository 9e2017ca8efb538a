"""One module per `interbot` subcommand; each registered by entry point in setup.cfg."""
