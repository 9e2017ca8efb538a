"""The tablet page's own behaviour in headless Chromium, without a robot: every sequence of
screens (typed after buttons, buttons after typed, the same question again, reload anywhere),
ten answers on a phone and on both tablet orientations, the robot gone and back (with a new
token), two tablets, the information screen with its picture, and feedback at the first touch.

One browser serves the whole module; each test gets its own server (a robot) and page."""
from __future__ import annotations

import threading
import time

import pytest
from PIL import Image
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support.ui import WebDriverWait

from robots.tablet import WebTouchScreen
from tests.browser import chromium

CATEGORIES = ("Bread and bakery", "Breakfast cereals", "Coffee and tea", "Pasta and rice",
              "Canned food", "Snacks and sweets", "Drinks", "Household", "Dairy",
              "Fruit and vegetables")
SIZES = {"phone": (360, 740, True), "tablet-portrait": (800, 1280, True),
         "tablet-landscape": (1280, 800, True), "desktop": (1024, 700, False)}
LONG_CAPTION = ("What are you looking for? Choose a category or type a name, for example "
                "milk, coffee or bread.")


@pytest.fixture(scope="module")
def browser():
    with chromium() as driver:
        yield driver


@pytest.fixture
def robot(tmp_path):
    """A robot's tablet server, paired through a secret of its own."""
    screen = WebTouchScreen("127.0.0.1", 0, secret_file=tmp_path / "tablet-secret")
    yield screen
    screen.close()


@pytest.fixture
def page(browser, robot):
    browser.execute_cdp_cmd("Emulation.clearDeviceMetricsOverride", {})
    browser.get(robot.url)
    until(browser, lambda d: mode(d) == "idle")
    yield robot, browser
    for handle in browser.window_handles[1:]:
        browser.switch_to.window(handle)
        browser.close()
    browser.switch_to.window(browser.window_handles[0])
    browser.get("about:blank")             # no page keeps looking for this test's robot


def until(driver, condition, timeout: float = 5.0):
    return WebDriverWait(driver, timeout, poll_frequency=0.02).until(condition)


def mode(driver) -> str:
    return driver.find_element(By.ID, "screen").get_attribute("data-mode")


def state(driver) -> dict:
    """What the page shows, read in one go."""
    return driver.execute_script("""
        const main = document.getElementById('screen');
        const visible = e => e.offsetParent !== null;
        return {mode: main.dataset.mode, why: main.dataset.why || null,
                prompt: document.getElementById('question').dataset.prompt || null,
                question: visible(document.getElementById('question-text'))
                          ? document.getElementById('question-text').textContent : null,
                notice: document.getElementById('notice').textContent,
                pressed: document.querySelectorAll('button.pressed').length,
                sent: Array.from(document.querySelectorAll('button.sent'),
                                 b => b.dataset.value || b.id),
                enabled: Array.from(document.querySelectorAll('button.answer:not(:disabled)'))
                              .filter(visible).map(b => b.dataset.value || b.id)};""")


def question_on(driver, prompt: str, ask: int | None = None) -> dict:
    until(driver, lambda d: state(d)["mode"] == "question" and state(d)["prompt"] == prompt)
    return state(driver)


def wait_press(screen, timeout: float = 5.0):
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        press = screen.take_press()
        if press is not None:
            return press
        time.sleep(0.005)
    return None


def click(driver, value: str) -> None:
    driver.find_element(By.CSS_SELECTOR, f'#buttons button[data-value="{value}"]').click()


def test_typed_answer_and_feedback_on_touch(page):
    screen, driver = page
    screen.show("name", "What is your name?", ("skip",), typed=True)
    until(driver, lambda d: mode(d) == "question")
    button = driver.find_element(By.CSS_SELECTOR, "#buttons button")
    screen.caption("Please type your name.")                  # a new caption only
    until(driver, lambda d: d.find_element(By.ID, "caption").text == "Please type your name.")
    assert button.text == "skip"                              # the same element: not rebuilt
    driver.find_element(By.ID, "typed-text").send_keys("Ada Lovelace")
    driver.find_element(By.ID, "typed-send").click()
    assert wait_press(screen) == ("name", "Ada Lovelace")
    sent = driver.find_element(By.ID, "typed-send")
    assert "pressed" in sent.get_attribute("class") and button.get_attribute("disabled")
    until(driver, lambda d: "sent" in sent.get_attribute("class"))


def test_every_sequence_of_buttons_and_typed_questions(page):
    screen, driver = page
    screen.show("what", "How can I help you?", ("Find a product", "Follow me"))
    question_on(driver, "what")
    click(driver, "Find a product")
    assert wait_press(screen) == ("what", "Find a product")
    # typed after buttons: OK and Enter work (they stayed disabled before)
    screen.show("product", "What are you looking for?", CATEGORIES, typed=True)
    shown = question_on(driver, "product")
    assert "typed-send" in shown["enabled"] and shown["pressed"] == 0 and shown["sent"] == []
    driver.find_element(By.ID, "typed-text").send_keys("milk" + Keys.ENTER)
    assert wait_press(screen) == ("product", "milk")
    # buttons after typed
    screen.show("confirm", "Did you mean Milk?", ("Yes", "No"))
    shown = question_on(driver, "confirm")
    assert shown["enabled"] == ["Yes", "No"] and shown["pressed"] == 0
    click(driver, "No")
    assert wait_press(screen) == ("confirm", "No")
    # typed after typed, with a button pressed in between: the field is empty and usable
    screen.show("product", "What are you looking for?", CATEGORIES, typed=True)
    question_on(driver, "product")
    field = driver.find_element(By.ID, "typed-text")
    assert field.get_attribute("value") == "" and field.is_enabled()
    field.send_keys("coffee")
    driver.find_element(By.ID, "typed-send").click()
    assert wait_press(screen) == ("product", "coffee")
    # the same question again (a loop): asked anew, both answers count
    for answer in ("Yes, please", "No, thank you"):
        screen.show("more", "Anything else?", ("Yes, please", "No, thank you"))
        until(driver, lambda d: state(d)["prompt"] == "more" and len(state(d)["enabled"]) == 2)
        click(driver, answer)
        assert wait_press(screen) == ("more", answer)
    screen.clear()
    until(driver, lambda d: mode(d) == "idle")


def test_reload_anywhere_gives_the_screen_back_as_it_is(page, tmp_path):
    screen, driver = page
    screen.show("q1", "Coffee?", ("yes", "no"))
    question_on(driver, "q1")
    driver.refresh()                                   # a question not yet answered
    assert question_on(driver, "q1")["enabled"] == ["yes", "no"]
    click(driver, "yes")
    assert wait_press(screen) == ("q1", "yes")
    driver.refresh()                                   # answered, before the robot moves on
    until(driver, lambda d: state(d)["sent"] == ["yes"])
    after = state(driver)
    assert after["enabled"] == [] and after["notice"] == ""     # this tablet answered it
    picture = tmp_path / "room.png"
    Image.new("RGB", (40, 30), (200, 30, 30)).save(picture)
    screen.display("Room N2", str(picture))
    until(driver, lambda d: mode(d) == "info")
    driver.refresh()                                   # an information screen
    until(driver, lambda d: mode(d) == "info")
    screen.show("name", "Your name?", ("skip",), typed=True)
    question_on(driver, "name")
    driver.refresh()                                   # a typed question
    question_on(driver, "name")
    driver.find_element(By.ID, "typed-text").send_keys("Ada" + Keys.ENTER)
    assert wait_press(screen) == ("name", "Ada")


LAYOUT = """
const inView = r => r.top >= -0.5 && r.left >= -0.5 && r.bottom <= innerHeight + 0.5
                    && r.right <= innerWidth + 0.5;
const rect = id => document.getElementById(id).getBoundingClientRect();
const caption = rect('caption');
const topAt = (e, r) => document.elementFromPoint((r.left + r.right) / 2,
                                                  (r.top + r.bottom) / 2);
const heading = rect('question-text'), field = rect('typed-text');
const result = {width: innerWidth, height: innerHeight,
                question: inView(heading) && heading.bottom <= caption.top
                          && topAt(null, heading) === document.getElementById('question-text'),
                field: inView(field) && field.bottom <= caption.top
                       && topAt(null, field) === document.getElementById('typed-text'),
                unreachable: [], overflowing: []};
for (const b of document.querySelectorAll('#buttons button')) {
  b.scrollIntoView({block: 'nearest'});
  const r = b.getBoundingClientRect();
  if (!inView(r) || r.bottom > caption.top || topAt(null, r) !== b) {
    result.unreachable.push(b.dataset.value);
  }
  if (b.scrollWidth > b.clientWidth || b.scrollHeight > b.clientHeight) {
    result.overflowing.push(b.dataset.value);          // its label does not fit the button
  }
}
const h = rect('question-text');                 // still in sight after scrolling the answers
result.questionAfterScroll = inView(h) && h.bottom <= caption.top;
return result;"""


MANY = tuple(f"Aisle {n} products" for n in range(1, 31))


@pytest.mark.parametrize("size, answers", [(size, CATEGORIES) for size in SIZES]
                         + [("phone", MANY), ("tablet-landscape", MANY)])
def test_many_answers_fit_or_scroll_with_the_question_and_field_in_sight(page, size, answers):
    screen, driver = page
    width, height, mobile = SIZES[size]
    driver.execute_cdp_cmd("Emulation.setDeviceMetricsOverride", {
        "width": width, "height": height, "deviceScaleFactor": 1, "mobile": mobile})
    screen.show("product", "What are you looking for? Choose a category or type a name.",
                answers, typed=True)
    screen.caption(LONG_CAPTION)
    question_on(driver, "product")
    until(driver, lambda d: d.find_element(By.ID, "caption").text == LONG_CAPTION)
    layout = driver.execute_script(LAYOUT)
    assert (layout["width"], layout["height"]) == (width, height)
    assert layout["question"] and layout["field"], layout
    assert layout["unreachable"] == layout["overflowing"] == [], layout
    assert layout["questionAfterScroll"], layout
    click(driver, answers[-1])                         # the last one, scrolled to, is pressed
    assert wait_press(screen) == ("product", answers[-1])


def test_the_robot_gone_and_back_with_a_new_token(page, tmp_path):
    screen, driver = page
    port, secret = screen.server.port, tmp_path / "tablet-secret"
    screen.show("q1", "Coffee?", ("yes", "no"))
    question_on(driver, "q1")
    screen.close()                                     # the robot's process ends
    until(driver, lambda d: state(d)["why"] in ("gone", "new-key"))
    gone = state(driver)
    assert gone["mode"] == "offline" and gone["question"] is None and gone["pressed"] == 0
    assert driver.find_element(By.ID, "offline").text.startswith("The robot is not running")
    back = WebTouchScreen("127.0.0.1", port, secret_file=secret)      # restarted: a new token
    try:
        assert back.guard.token != screen.guard.token
        back.show("q2", "Tea?", ("yes", "no"))
        assert question_on(driver, "q2", 5)["enabled"] == ["yes", "no"]
        click(driver, "no")
        assert wait_press(back) == ("q2", "no")
    finally:
        back.close()
    until(driver, lambda d: state(d)["why"] == "gone")
    stranger = WebTouchScreen("127.0.0.1", port, secret_file=tmp_path / "another-secret")
    try:                                               # back, but it does not know this tablet
        until(driver, lambda d: state(d)["why"] == "new-key")
        assert "does not know this tablet" in driver.find_element(By.ID, "offline").text
    finally:
        stranger.close()


def test_a_robot_that_hangs_after_a_touch_leaves_nothing_pressed(page):
    screen, driver = page
    screen.show("q1", "Coffee?", ("yes", "no"))
    question_on(driver, "q1")
    hung = threading.Event()
    screen.app.state.hub.loop.call_soon_threadsafe(hung.wait, 10.0)   # the server hangs …
    try:
        click(driver, "yes")
        until(driver, lambda d: state(d)["mode"] == "offline", timeout=5.0)
        assert state(driver)["pressed"] == 0
    finally:
        hung.set()                                     # … until the page has given up
    until(driver, lambda d: state(d)["mode"] == "question", timeout=5.0)   # back afterwards
    assert wait_press(screen) == ("q1", "yes")         # the press arrived late: it counted …
    until(driver, lambda d: state(d)["sent"] == ["yes"])   # … and the page shows it so


def test_two_tablets_the_one_that_lost_is_told_who_answered(page):
    screen, driver = page
    screen.show("q1", "Coffee?", ("yes", "no"))
    first = driver.current_window_handle
    question_on(driver, "q1")
    driver.switch_to.new_window("tab")
    second = driver.current_window_handle
    driver.get(screen.url + "&name=Checkout")         # a tablet may be given a name
    question_on(driver, "q1")
    driver.switch_to.window(first)
    click(driver, "yes")
    assert wait_press(screen) == ("q1", "yes")
    driver.switch_to.window(second)                    # the other tablet sees it at once
    until(driver, lambda d: state(d)["sent"] == ["yes"])
    seen = state(driver)
    assert seen["enabled"] == [] and seen["notice"] == "Answered on another tablet: “yes”"
    screen.show("q0", "Milk?", ("yes", "no"))          # the named tablet answers
    question_on(driver, "q0")
    click(driver, "no")
    assert wait_press(screen) == ("q0", "no")
    driver.switch_to.window(first)
    until(driver, lambda d: state(d)["notice"] == "Answered on the tablet “Checkout”: “no”")
    # both press at the same moment: the server holds both presses, takes one, refuses one
    screen.show("q2", "Tea?", ("yes", "no"))
    question_on(driver, "q2")
    driver.switch_to.window(second)
    question_on(driver, "q2")
    driver.switch_to.window(first)
    held = threading.Event()
    screen.app.state.hub.loop.call_soon_threadsafe(held.wait, 10.0)
    try:
        click(driver, "yes")
        driver.switch_to.window(second)
        click(driver, "no")
    finally:
        held.set()                                     # both presses wait in the server
    winner = wait_press(screen)
    assert winner is not None and winner[0] == "q2" and screen.take_press() is None
    notices = {}
    for handle in (first, second):
        driver.switch_to.window(handle)
        until(driver, lambda d: state(d)["sent"] == [winner[1]])
        notices[handle] = state(driver)["notice"]
    loser = second if winner[1] == "yes" else first
    where = "the tablet “Checkout”" if loser == first else "another tablet"
    assert notices[loser] in (f"Already answered on {where}: “{winner[1]}”",
                              f"Answered on {where}: “{winner[1]}”")
    assert notices[first if loser == second else second] == ""


def test_information_screen_shows_its_picture(page, tmp_path):
    screen, driver = page
    picture = tmp_path / "room.png"
    Image.new("RGB", (120, 80), (200, 30, 30)).save(picture)
    screen.display("Room N2 is the second door on the left.", str(picture))
    until(driver, lambda d: mode(d) == "info")
    assert driver.find_element(By.ID, "info-text").text.startswith("Room N2")
    until(driver, lambda d: d.execute_script(
        "return document.getElementById('info-picture').naturalWidth") == 120)
    screen.clear()
    until(driver, lambda d: mode(d) == "idle")
