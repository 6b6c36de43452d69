"""`cover view` in a real browser: headless Chromium driven by Selenium (Debian's chromium,
chromium-driver and python3-selenium). The page's frames must be the bytes `cover render` writes
for the same view; a drag, the section slider, leaf toggles, a click and an edit of the scene
file must do what docs/viewer.md says. COVER_VIEWER_SCREENSHOT=PATH saves the page as a PNG
(the README's picture)."""

import json
import os
import pathlib
import shutil
import subprocess
import urllib.parse
import urllib.request

import pytest
from selenium import webdriver
from selenium.webdriver.chrome.service import Service
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By
from selenium.webdriver.common.keys import Keys
from selenium.webdriver.support.ui import Select, WebDriverWait

import cover

from conftest import COVER_BIN, MODELS, run_cli

CHROMEDRIVER = shutil.which("chromedriver") or "/usr/bin/chromedriver"


@pytest.fixture(scope="module")
def scene(tmp_path_factory):
    d = tmp_path_factory.mktemp("view")
    shutil.copy(MODELS / "default.json", d / "scene.json")
    shutil.copy(MODELS / "torus.off", d / "torus.off")
    return d / "scene.json"


@pytest.fixture(scope="module")
def server(scene):
    p = subprocess.Popen([str(COVER_BIN), "view", str(scene), "--json", "--poll", "0.2"],
                         stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        line = p.stdout.readline()
        assert line, p.stderr.read()
        yield json.loads(line)["url"]
    finally:
        p.terminate()
        assert p.wait(timeout=20) == 0  # SIGTERM stops it cleanly


@pytest.fixture(scope="module")
def browser():
    o = webdriver.ChromeOptions()
    o.binary_location = shutil.which("chromium") or "/usr/bin/chromium"
    for a in ("--headless=new", "--no-sandbox", "--disable-dev-shm-usage", "--disable-gpu",
              "--window-size=1180,760", "--force-device-scale-factor=1"):
        o.add_argument(a)
    d = webdriver.Chrome(service=Service(CHROMEDRIVER), options=o)
    try:
        yield d
    finally:
        d.quit()


def frame(driver):
    return driver.find_element(By.ID, "frame")


def wait_idle(driver, other_than=None, timeout=60, showing=""):
    """Waits for the full-size frame of a view other than `other_than` whose URL contains
    `showing` (an event's frame, not the one still on screen when it fired); returns its URL."""
    def ready(d):
        f = frame(d)
        url = f.get_attribute("data-url")
        return (f.get_attribute("data-state") == "idle" and url and url != other_than and
                showing in url and url)
    return WebDriverWait(driver, timeout, poll_frequency=0.05).until(ready)


def open_page(driver, url):
    driver.get(url)
    return wait_idle(driver)


def fetch(base, relative):
    return urllib.request.urlopen(urllib.parse.urljoin(base, relative), timeout=60).read()


def params(relative):
    return dict(urllib.parse.parse_qsl(urllib.parse.urlsplit(relative).query))


def cli_render(scene, p, out):
    """`cover render` with the flags named as the frame's parameters."""
    args = ["render", scene, "-o", out, "--size", f"{p['w']}x{p['h']}", "--view", p["view"],
            "--up", p["up"], "--azimuth", p["azimuth"], "--zoom", p["zoom"],
            "--samples", p["samples"], "--crease", p.get("crease", "30"), "--quiet"]
    if "elevation" in p:
        args += ["--elevation", p["elevation"]]
    if "pan" in p:
        args += ["--pan", p["pan"]]
    if "section" in p:
        args += ["--section", p["section"]]
    if p.get("fit") == "1":
        args.append("--fit")
    if p.get("perspective") == "1":
        args.append("--perspective")
    if p.get("outline") == "0":
        args.append("--no-outline")
    run_cli(*args)
    return pathlib.Path(out).read_bytes()


def test_page_frame_is_cover_render_byte_for_byte(server, browser, scene, tmp_path):
    url = open_page(browser, server)
    p = params(url)
    assert (p["view"], p["up"], p["samples"]) == ("iso", "z", "2")
    png = fetch(server, url)
    assert png[:8] == b"\x89PNG\r\n\x1a\n"
    assert png == cli_render(scene, p, tmp_path / "r.png")


def test_drag_orbits_and_the_frame_follows(server, browser, scene, tmp_path):
    before = open_page(browser, server)
    ActionChains(browser).move_to_element(frame(browser)).click_and_hold() \
        .move_by_offset(60, 0).move_by_offset(60, 25).release().perform()
    after = wait_idle(browser, other_than=before)
    pa, pb = params(after), params(before)
    assert float(pa["azimuth"]) != float(pb["azimuth"])
    assert "elevation" in pa  # a vertical move set it from the view's own
    png = fetch(server, after)
    assert png != fetch(server, before)
    assert png == cli_render(scene, pa, tmp_path / "r.png")


def test_section_slider_moves_the_cut(server, browser, scene, tmp_path):
    open_page(browser, server)
    Select(browser.find_element(By.ID, "section-axis")).select_by_visible_text("z")
    first = wait_idle(browser, showing="section=")
    cut = params(first)["section"].split(",")
    assert cut[:3] == ["0", "0", "1"]
    slider = browser.find_element(By.ID, "section-offset")
    slider.send_keys(*([Keys.ARROW_LEFT] * 150))
    second = wait_idle(browser, other_than=first)
    moved = params(second)["section"].split(",")
    assert float(moved[3]) < float(cut[3])
    png = fetch(server, second)
    assert png != fetch(server, first)
    assert png == cli_render(scene, params(second), tmp_path / "r.png")


def test_click_reports_the_class_classify_gives(server, browser, scene, tmp_path):
    open_page(browser, server)
    img = frame(browser)
    seen = 0
    for dx, dy in ((0, 0), (-150, 40), (120, -60), (260, 0), (-300, -200)):
        browser.execute_script("document.getElementById('pick').dataset.result = ''")
        ActionChains(browser).move_to_element_with_offset(img, dx, dy).click().perform()
        WebDriverWait(browser, 30).until(
            lambda d: d.find_element(By.ID, "pick").get_attribute("data-result"))
        r = json.loads(browser.find_element(By.ID, "pick").get_attribute("data-result"))
        if not r["hit"]:
            continue
        seen += 1
        pts = tmp_path / "p.txt"
        pts.write_text("%r %r %r\n" % tuple(r["point"]))
        want = run_cli("classify", scene, "--points", pts).stdout.split()[0]
        assert r["class"] == want
        assert r["leaf"] in {"box", "sphere", "cylinder", "section cap"} or \
            r["leaf"].endswith("torus.off")
    assert seen >= 2


def test_hiding_a_leaf_leaves_it_out_of_the_scene(server, browser, scene, tmp_path):
    before = open_page(browser, server)
    box = browser.find_element(By.CSS_SELECTOR, "#leaves input[data-leaf='5']")  # the torus
    box.click()
    after = wait_idle(browser, other_than=before, showing="hidden=")
    assert params(after)["hidden"] == "5"
    # The same scene without the torus node, rendered by the CLI: the same bytes.
    s = json.loads(scene.read_text())
    del s["union"][1]
    pruned = tmp_path / "pruned.json"
    pruned.write_text(json.dumps(s))
    p = params(after)
    del p["hidden"]
    assert fetch(server, after) == cli_render(pruned, p, tmp_path / "r.png")


def test_editing_the_scene_reloads_it_and_keeps_the_view(server, browser, scene, tmp_path):
    opened = open_page(browser, server)
    ActionChains(browser).move_to_element(frame(browser)).click_and_hold() \
        .move_by_offset(-80, 10).release().perform()
    turned = wait_idle(browser, other_than=opened)
    version = browser.find_element(By.TAG_NAME, "body").get_attribute("data-version")
    original = scene.read_text()
    try:
        # A broken file: the page says so and keeps the last good model.
        scene.write_text(original.replace('"union"', '"onion"'))
        WebDriverWait(browser, 30).until(
            lambda d: "reload failed" in d.find_element(By.ID, "error").text)
        assert "onion" in browser.find_element(By.ID, "error").text
        # A real edit: a smaller sphere.
        scene.write_text(original.replace('"radius": 2.65', '"radius": 2.3'))
        WebDriverWait(browser, 30).until(
            lambda d: d.find_element(By.TAG_NAME, "body").get_attribute("data-version")
            != version)
        reloaded = wait_idle(browser, other_than=None)
        assert params(reloaded)["azimuth"] == params(turned)["azimuth"]
        WebDriverWait(browser, 30).until(
            lambda d: d.find_element(By.ID, "error").text == "")
        png = fetch(server, reloaded)
        assert png == cli_render(scene, params(reloaded), tmp_path / "r.png")
        assert png != cli_render(MODELS / "default.json", params(reloaded), tmp_path / "o.png")
    finally:
        scene.write_text(original)


def test_screenshot_for_the_readme(server, browser):
    path = os.environ.get("COVER_VIEWER_SCREENSHOT")
    if not path:
        pytest.skip("COVER_VIEWER_SCREENSHOT not set")
    open_page(browser, server)
    Select(browser.find_element(By.ID, "section-axis")).select_by_visible_text("y")
    wait_idle(browser, showing="section=")
    browser.find_element(By.ID, "flip").click()  # keep y > 0: the cut faces the camera
    wait_idle(browser, showing="section=0%2C-1")
    ActionChains(browser).move_to_element_with_offset(frame(browser), -90, 10).click().perform()
    WebDriverWait(browser, 30).until(
        lambda d: d.find_element(By.ID, "pick").get_attribute("data-result"))
    browser.save_screenshot(path)


def test_python_view_serves_the_same_frames(scene, tmp_path):
    with cover.view(scene) as v:
        assert v.version == 1 and v.error == ""
        base = v.url
        q = "frame?" + urllib.parse.urlencode(
            {"t": params(base)["t"], "w": 160, "h": 120, "view": "front", "up": "z",
             "azimuth": 20, "zoom": 1.5, "samples": 1, "pan": "0.1,-0.05"})
        png = fetch(base, q)
        assert png == cli_render(scene, params(q), tmp_path / "r.png")
        # Without the token: refused.
        with pytest.raises(urllib.error.HTTPError) as e:
            fetch(base, "frame?w=10&h=10")
        assert e.value.code == 403
    with pytest.raises(cover.InputError, match="nope.json"):
        cover.view(tmp_path / "nope.json")
