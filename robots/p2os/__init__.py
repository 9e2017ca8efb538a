"""P2OS, the serial protocol of ActivMedia Pioneer 2 bases (HOROS).

`protocol` is the pure codec and byte-fed parser, `driver` the `Base` over a serial link,
`emulator` the firmware for tests and the simulated world.
"""
