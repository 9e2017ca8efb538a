"""Sound devices: speech out through espeak-ng (espeak.py), sound in from a file or a microphone
(source.py), and recognition of the few answers on the screen (recognizer.py, pocketsphinx)."""
