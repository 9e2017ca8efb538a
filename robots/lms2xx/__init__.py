"""SICK LMS 2xx (LMS200, LMS291), the laser of the Pioneer-II and B21r era, over RS-232/RS-422.

`protocol` is the pure telegram codec and byte-fed parser, `driver` the `Laser` over a serial
link, `emulator` the laser's firmware scanning the simulated world. docs/lasers.md.
"""
