"""Sound in: a WAV file (tests, recorded sessions) or the robot's microphone (arecord).

Both deliver what the recognizer wants: 16 kHz, mono, signed 16-bit little-endian samples.
"""
from __future__ import annotations

import queue
import shutil
import subprocess
import threading
import time
import wave
from fractions import Fraction
from pathlib import Path

import numpy as np

from robots.devices import AudioSource
from robots.exceptions import RobotError

RATE = 16000


class WavFileSource(AudioSource):
    """A WAV file, converted to 16 kHz mono, with `pad` seconds of silence either side (so that
    the recognizer hears where speech starts and ends)."""

    def __init__(self, path: str | Path, pad: float = 0.5) -> None:
        self.path = Path(path)
        try:
            with wave.open(str(self.path)) as wav:
                if wav.getsampwidth() != 2:
                    raise RobotError(f"{self.path}: only 16-bit PCM WAV files can be listened "
                                     f"to (this one has {8 * wav.getsampwidth()}-bit samples)")
                rate, channels = wav.getframerate(), wav.getnchannels()
                samples = np.frombuffer(wav.readframes(wav.getnframes()), dtype="<i2")
        except (OSError, EOFError, wave.Error) as exc:
            raise RobotError(f"{self.path}: cannot read as a WAV file: {exc}") from exc
        samples = samples.reshape(-1, channels).mean(axis=1)
        samples = _resample(samples, rate)
        silence = np.zeros(int(pad * RATE))
        whole = np.concatenate([silence, samples, silence])
        self._data = np.clip(whole, -32768, 32767).astype("<i2").tobytes()
        self._offset = 0

    def read(self, frames: int) -> bytes | None:
        if self._offset >= len(self._data):
            return None
        chunk = self._data[self._offset:self._offset + 2 * frames]
        self._offset += len(chunk)
        return chunk


class WavQueueSource(AudioSource):
    """WAV files heard one per question (`--listen FILE.wav` or `--listen FOLDER`): the
    recognizer calls `cue()` when a question appears, and the next file (in name order) plays,
    padded with silence; between files the source is silent. After the last file it ends."""

    WAIT = 0.05     # s to pause when there is nothing to play (no busy loop)

    def __init__(self, path: str | Path) -> None:
        path = Path(path)
        if path.is_dir():
            self.paths = sorted(p for p in path.iterdir() if p.suffix.lower() == ".wav")
            if not self.paths:
                raise RobotError(f"{path}: the folder holds no .wav files to listen to")
        elif path.is_file():
            self.paths = [path]
        else:
            raise RobotError(f"{path}: no such WAV file or folder to listen to")
        self._next = 0
        self._playing: WavFileSource | None = None
        self.played: list[Path] = []

    def cue(self) -> None:
        """A question appeared: play the next file (the rest of the one playing is dropped)."""
        if self._next < len(self.paths):
            self._playing = WavFileSource(self.paths[self._next])
            self.played.append(self.paths[self._next])
            self._next += 1

    def read(self, frames: int) -> bytes | None:
        if self._playing is not None:
            chunk = self._playing.read(frames)
            if chunk is not None:
                return chunk
            self._playing = None
        if self._next >= len(self.paths):
            return None
        time.sleep(self.WAIT)
        return b""


def _resample(samples: np.ndarray, rate: int) -> np.ndarray:
    if rate == RATE:
        return samples.astype(np.float64)
    from scipy.signal import resample_poly
    ratio = Fraction(RATE, rate).limit_denominator(1000)
    return resample_poly(samples.astype(np.float64), ratio.numerator, ratio.denominator)


class MicrophoneSource(AudioSource):
    """The default (or a named ALSA) capture device, read by `arecord` in a subprocess."""

    START_CHECK = 0.3     # s: arecord fails at once when there is no capture device

    def __init__(self, device: str | None = None) -> None:
        executable = shutil.which("arecord")
        if executable is None:
            raise RobotError("no microphone: `arecord` is missing (apt-get install alsa-utils)")
        command = [executable, "-q", "-t", "raw", "-f", "S16_LE", "-r", str(RATE), "-c", "1"]
        if device:
            command += ["-D", device]
        self._process = subprocess.Popen(command, stdin=subprocess.DEVNULL,
                                         stdout=subprocess.PIPE, stderr=subprocess.PIPE)
        time.sleep(self.START_CHECK)
        if self._process.poll() is not None:
            error = self._process.stderr.read().decode(errors="replace").strip()
            raise RobotError(f"no microphone: arecord{' -D ' + device if device else ''} "
                             f"failed: {error or 'exit code ' + str(self._process.returncode)} "
                             f"(is a capture device connected? `arecord -l` lists them)")
        self._chunks: queue.Queue[bytes | None] = queue.Queue()
        self._reader = threading.Thread(target=self._read_loop, name="microphone", daemon=True)
        self._reader.start()

    def _read_loop(self) -> None:
        stream = self._process.stdout
        while True:
            chunk = stream.read1(3200) if hasattr(stream, "read1") else stream.read(3200)
            if not chunk:
                self._chunks.put(None)
                return
            self._chunks.put(chunk)

    def read(self, frames: int) -> bytes | None:
        try:
            return self._chunks.get(timeout=0.1)
        except queue.Empty:
            return b""

    def close(self) -> None:
        if self._process.poll() is None:
            self._process.terminate()
            try:
                self._process.wait(timeout=2.0)
            except subprocess.TimeoutExpired:
                self._process.kill()
