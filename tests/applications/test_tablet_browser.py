"""The tablet page in a real browser (headless Chromium) during a real-time simulated survey:
a person answers every question by clicking, while the simulated person only stands there.

One run covers the whole story: the page needs its token, two tabs show the same question, a
reloaded tab gets the current screen back, the screenshot shows the question, and the answers
clicked arrive in SQLite and in the trace as `touch` answers.
"""
from __future__ import annotations

import io
import re
import shutil
import sqlite3
import subprocess
import sys

import pytest
from PIL import Image
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

from applications.graph.loader import find_application
from applications.trace import read_trace
from tests.browser import chromium

# A person who walks up to the robot and stays, never touching the simulated screen.
SILENT_PERSON = """
[scenario]
name = "silent"
duration = 60.0
robot = "robot_home"
[[person]]
id = "visitor"
appear = 1.0
at = [1.5, 0.3]
speed = 1.0
steps = [ { approach = 0.5 }, { pause = 300.0 } ]
"""
ANSWERS = {"q1": "yes", "q2": "4", "q3": "no"}
RUN_SECONDS = "40"


@pytest.fixture
def quick_survey(tmp_path):
    """The bundled survey, waiting 1 s instead of 30 s before it attracts a new person."""
    folder = tmp_path / "survey"
    shutil.copytree(find_application("survey"), folder)
    graph = folder / "graph.xml"
    text = graph.read_text()
    assert "time_in_state > 30s and people.new" in text
    graph.write_text(text.replace("time_in_state > 30s and people.new",
                                  "time_in_state > 1s and people.new"))
    scenario = tmp_path / "silent.toml"
    scenario.write_text(SILENT_PERSON)
    return folder, scenario


def shown(driver) -> dict:
    """What the page shows, read in one go (the page may re-render between two WebDriver calls)."""
    return driver.execute_script("""
        const section = document.getElementById('question');
        return {mode: document.getElementById('screen').dataset.mode,
                prompt: section.dataset.prompt || null,
                text: document.getElementById('question-text').textContent,
                buttons: Array.from(document.querySelectorAll('#buttons button'),
                                    b => b.textContent)};""")


def wait_for_question(driver, prompt: str, timeout: float = 30.0) -> dict:
    WebDriverWait(driver, timeout, poll_frequency=0.05).until(
        lambda d: shown(d)["mode"] == "question" and shown(d)["prompt"] == prompt)
    return shown(driver)


@pytest.mark.slow
def test_a_person_answers_the_whole_survey_on_the_page(quick_survey, tmp_path):
    folder, scenario = quick_survey
    data, trace = tmp_path / "data", tmp_path / "run.jsonl"
    run = subprocess.Popen([sys.executable, "-m", "applications.cli", "run", str(folder),
                            "--gui", "127.0.0.1:0", "--scenario", str(scenario),
                            "--duration", RUN_SECONDS, "--data", str(data), "--trace", str(trace),
                            "--quiet"], stdout=subprocess.PIPE, text=True)
    try:
        url = None
        for line in run.stdout:
            found = re.search(r"tablet page at (http://127\.0\.0\.1:\d+/\?token=\S+)", line)
            if found:
                url = found.group(1)
                break
        assert url is not None, "the run did not print the tablet page's URL"
        with chromium() as driver:
            driver.get(url.split("token=")[0] + "token=wrong")
            assert "403" in driver.find_element(By.TAG_NAME, "body").text
            driver.get(url)
            first = wait_for_question(driver, "q1")
            assert first["text"] == "Do you like working on this floor?"
            assert first["buttons"] == ["yes", "no"]
            png = driver.get_screenshot_as_png()
            picture = Image.open(io.BytesIO(png)).convert("L")
            assert picture.size[0] >= 800 and len(png) > 10_000
            assert len(picture.getcolors(256)) > 20     # text and buttons, not a blank page

            main_tab = driver.current_window_handle
            driver.switch_to.new_window("tab")
            driver.get(url)
            assert wait_for_question(driver, "q1") == first      # a second tablet sees the same
            driver.close()
            driver.switch_to.window(main_tab)
            driver.refresh()                                      # a reconnecting tablet
            assert wait_for_question(driver, "q1") == first

            for prompt, answer in ANSWERS.items():
                question = wait_for_question(driver, prompt)
                assert answer in question["buttons"]
                driver.find_element(By.CSS_SELECTOR, f'#buttons button[data-value="{answer}"]').click()
            WebDriverWait(driver, 30, poll_frequency=0.1).until(
                lambda d: shown(d)["mode"] == "idle")
        run.wait(timeout=120)
    finally:
        if run.poll() is None:
            run.kill()
            run.wait()
        run.stdout.close()
    assert run.returncode == 0
    with sqlite3.connect(data / "survey.sqlite") as db:
        stored = dict(db.execute("SELECT question, answer FROM answers ORDER BY id").fetchall())
    assert stored == ANSWERS
    answers = [e for e in read_trace(trace) if e["kind"] == "answer"]
    assert [(e["question"], e["answer"], e["source"]) for e in answers] == [
        (q, a, "touch") for q, a in ANSWERS.items()]
