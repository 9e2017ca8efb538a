"""The tablet page's own behaviour in headless Chromium, without a robot: typed answers, the
information screen with its picture (fetched by URL under the page's security policy), captions
that leave a question's buttons alone, and feedback at the first touch."""
from __future__ import annotations

import time

import pytest
from PIL import Image
from selenium.webdriver.common.by import By
from selenium.webdriver.support.ui import WebDriverWait

from robots.tablet import WebTouchScreen
from tests.browser import chromium


@pytest.fixture
def page():
    screen = WebTouchScreen("127.0.0.1", 0)
    with chromium() as driver:
        driver.get(screen.url)
        WebDriverWait(driver, 20).until(
            lambda d: d.find_element(By.ID, "screen").get_attribute("data-mode") == "idle")
        yield screen, driver
    screen.close()


def mode(driver) -> str:
    return driver.find_element(By.ID, "screen").get_attribute("data-mode")


def wait_press(screen, timeout: float = 10.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        press = screen.take_press()
        if press is not None:
            return press
        time.sleep(0.01)
    return None


def test_typed_answer_and_feedback_on_touch(page):
    screen, driver = page
    screen.show("name", "What is your name?", ("skip",), typed=True)
    WebDriverWait(driver, 10).until(lambda d: mode(d) == "question")
    button = driver.find_element(By.CSS_SELECTOR, "#buttons button")
    screen.caption("Please type your name.")                  # a new caption only
    WebDriverWait(driver, 10).until(
        lambda d: d.find_element(By.ID, "caption").text == "Please type your name.")
    assert button.text == "skip"                              # the same element: not rebuilt
    driver.find_element(By.ID, "typed-text").send_keys("Ada Lovelace")
    driver.find_element(By.ID, "typed-send").click()
    assert wait_press(screen) == ("name", "Ada Lovelace")
    sent = driver.find_element(By.ID, "typed-send")
    assert "pressed" in sent.get_attribute("class") and button.get_attribute("disabled")


def test_information_screen_shows_its_picture(page, tmp_path):
    screen, driver = page
    picture = tmp_path / "room.png"
    Image.new("RGB", (120, 80), (200, 30, 30)).save(picture)
    screen.display("Room N2 is the second door on the left.", str(picture))
    WebDriverWait(driver, 10).until(lambda d: mode(d) == "info")
    assert driver.find_element(By.ID, "info-text").text.startswith("Room N2")
    WebDriverWait(driver, 10).until(lambda d: d.execute_script(
        "return document.getElementById('info-picture').naturalWidth") == 120)
    screen.clear()
    WebDriverWait(driver, 10).until(lambda d: mode(d) == "idle")
