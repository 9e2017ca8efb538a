"""The bundled macro-behaviors, one module each; registered by entry point in setup.cfg."""
