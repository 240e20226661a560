"""One module per ``gearbox`` verb (see :mod:`gearbox.cli`)."""
