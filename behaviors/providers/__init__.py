"""The bundled percept providers (entry-point group `interbot.percepts`), one module each."""
