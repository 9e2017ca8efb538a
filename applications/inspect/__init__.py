"""The live inspector: a local web page showing every layer of a running robot."""
