"""`EspeakSpeaker`: text-to-speech with espeak-ng in a subprocess, so the tick never waits for it.

To the sound card by default; with `wav_dir` each utterance goes to a numbered WAV file instead
(0001.wav, with the text beside it in 0001.txt), for CI and machines without audio. A new
utterance cuts the old one off: the robot has moved on.
"""
from __future__ import annotations

import logging
import shutil
import subprocess
import wave
from pathlib import Path

from robots.devices import Speaker
from robots.exceptions import RobotError

log = logging.getLogger("interbot.speech")

EXECUTABLE = "espeak-ng"
INSTALL_HINT = "install it with `apt-get install espeak-ng` (the project's .ci/run does)"


def espeak_voices(language: str, executable: str = EXECUTABLE) -> list[str]:
    """The espeak-ng voice files that speak `language` (e.g. de, en, en-us)."""
    result = subprocess.run([executable, f"--voices={language}"], capture_output=True, text=True,
                            timeout=10, check=False)
    lines = result.stdout.splitlines()[1:]
    return [line.split()[4] for line in lines if len(line.split()) >= 5]


class EspeakSpeaker(Speaker):
    def __init__(self, clock, language: str = "en", voice: str | None = None,
                 wav_dir: str | Path | None = None, executable: str = EXECUTABLE) -> None:
        self.clock = clock
        self.executable = shutil.which(executable)
        if self.executable is None:
            raise RobotError(f"speech output needs {executable}, which is not on PATH; "
                             f"{INSTALL_HINT}")
        self.language = language
        self.voice = voice or language
        if not voice and not espeak_voices(language, self.executable):
            raise RobotError(f"espeak-ng has no voice for language '{language}' "
                             f"(try de, en, en-us, or name one with --voice)")
        self.wav_dir = Path(wav_dir) if wav_dir is not None else None
        if self.wav_dir is not None:
            self.wav_dir.mkdir(parents=True, exist_ok=True)
        self.count = 0
        self._process: subprocess.Popen | None = None
        self._wav: Path | None = None
        self._started = 0.0
        self._until = 0.0            # robot time the WAV utterance lasts until (WAV output)
        self._warned = False

    def say(self, text: str) -> None:
        self._cut_off()
        self.count += 1
        command = [self.executable, "-v", self.voice]
        self._wav = None
        if self.wav_dir is not None:
            self._wav = self.wav_dir / f"{self.count:04d}.wav"
            (self.wav_dir / f"{self.count:04d}.txt").write_text(text + "\n", encoding="utf-8")
            command += ["-w", str(self._wav)]
        command += ["--", text]
        self._started = self.clock.now()
        self._until = self._started
        try:
            self._process = subprocess.Popen(command, stdin=subprocess.DEVNULL,
                                             stdout=subprocess.DEVNULL, stderr=subprocess.PIPE)
        except OSError as exc:
            self._warn(f"espeak-ng could not start: {exc}")
            self._process = None

    def busy(self) -> bool:
        """While espeak-ng runs (it speaks until done); for WAV output, for the WAV's length."""
        process = self._process
        if process is not None:
            if process.poll() is None:
                return True
            self._finished(process)
        return self.clock.now() < self._until

    def busy_rendering(self) -> bool:
        """While espeak-ng still runs (for WAV output: the WAV is not complete yet)."""
        process = self._process
        return process is not None and process.poll() is None

    def _finished(self, process: subprocess.Popen) -> None:
        self._process = None
        error = process.stderr.read().decode(errors="replace").strip() if process.stderr else ""
        if process.stderr:
            process.stderr.close()
        if process.returncode not in (0, -15):
            self._warn(f"espeak-ng exited with code {process.returncode}: {error[:200]} "
                       f"(no sound card? --speech-wav DIR writes WAV files instead)")
        if self._wav is not None and self._wav.is_file():
            self._until = self._started + wav_duration(self._wav)

    def _cut_off(self) -> None:
        process = self._process
        if process is not None and process.poll() is None:
            process.terminate()
            try:
                process.wait(timeout=1.0)
            except subprocess.TimeoutExpired:
                process.kill()
        if process is not None:
            self._finished(process)
        self._until = self.clock.now()

    def _warn(self, message: str) -> None:
        if not self._warned:
            log.warning(message)
            self._warned = True

    def close(self) -> None:
        self._cut_off()


def wav_duration(path: Path) -> float:
    """Length of a WAV file, s (0 for one that cannot be read)."""
    try:
        with wave.open(str(path)) as wav:
            return wav.getnframes() / float(wav.getframerate())
    except (OSError, EOFError, wave.Error):
        return 0.0
