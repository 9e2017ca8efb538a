"""Hokuyo laser scanners (URG over USB serial, UST over Ethernet) speaking SCIP 2.0.

`protocol` is the pure codec (6-bit characters, check characters, reply blocks) and byte-fed
parser, `driver` the `Laser` over a serial port or socket, `emulator` the sensor's firmware
scanning the simulated world. docs/lasers.md.
"""
