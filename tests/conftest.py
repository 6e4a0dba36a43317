from pathlib import Path

import pytest

import transplanter.app.one_blas_thread  # noqa: F401 - the tests run as the command does: one BLAS thread
from transplanter.families import load_family

PARTS = Path(__file__).resolve().parents[1] / "parts"


@pytest.fixture(scope="session")
def parts_dir() -> Path:
    return PARTS


@pytest.fixture(scope="session")
def seed000_arms():
    from transplanter.families import ArmStudy

    fam = load_family(PARTS / "fourbar_seed000.py")
    return {p.name[-1]: p.arm for p in fam.parts if isinstance(p, ArmStudy)}


@pytest.fixture(scope="session")
def built(transplanter_built) -> Path:
    """Every seed family built once per test run, for the tests that read exports: the
    folder the pytest plugin built for the part items (``transplanter.app.pytest_plugin``; with
    pytest-xdist, one build shared by the workers)."""
    return transplanter_built


@pytest.fixture
def browser(chromium):
    """The run's headless Chromium, its console log emptied of what earlier tests' pages said
    (each test reads the errors of its own page only, whatever ran before it)."""
    chromium.get("about:blank")
    chromium.get_log("browser")
    return chromium


@pytest.fixture(scope="session")
def chromium(tmp_path_factory):
    """Headless Chromium driven by Selenium (Debian's chromium and chromium-driver, which
    ``.ci/run`` installs); the test is skipped where they are not installed."""
    import shutil

    if not (shutil.which("chromium") and shutil.which("chromedriver")):
        pytest.skip("Chromium/ChromeDriver not installed")
    webdriver = pytest.importorskip("selenium.webdriver")
    from selenium.webdriver.chrome.service import Service

    options = webdriver.ChromeOptions()
    profile = tmp_path_factory.mktemp("chromium-profile")
    for arg in (
        "--headless=new",
        "--no-sandbox",
        "--disable-gpu",
        "--disable-dev-shm-usage",
        "--disable-background-networking",
        "--no-first-run",
        "--window-size=1200,900",
        f"--user-data-dir={profile}",
    ):
        options.add_argument(arg)
    driver = webdriver.Chrome(service=Service(shutil.which("chromedriver")), options=options)
    yield driver
    driver.quit()
