//! The web UI end to end in a real browser: Debian's headless Chromium,
//! driven over WebDriver (chromedriver) by fantoccini.
//!
//! It starts `conquest serve` on a free loopback port, loads the page,
//! starts a simulation, waits until it completes, takes manual control of a
//! robot and drives it, cuts a robot's link and sees the page show the loss
//! and the recovery, restarts the server and sees the page reconnect, and
//! checks what the page shows. Screenshots of the views go to
//! `$CONQUEST_SCREENSHOTS` (default: a directory under `target/`).
//!
//! Without Chromium and chromedriver the test says so and passes, unless
//! `CONQUEST_REQUIRE_BROWSER` is set (CI sets it: there it must run).

mod common;

use common::{Server, fields_dir};
use fantoccini::key::Key;
use fantoccini::{Client, ClientBuilder, Locator};
use std::path::{Path, PathBuf};
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

const CHROMIUM: &str = "/usr/bin/chromium";
const CHROMEDRIVER: &str = "/usr/bin/chromedriver";

struct Driver(Child);

impl Drop for Driver {
    fn drop(&mut self) {
        let _ = self.0.kill();
        let _ = self.0.wait();
    }
}

fn free_port() -> u16 {
    std::net::TcpListener::bind("127.0.0.1:0")
        .and_then(|l| l.local_addr())
        .map(|a| a.port())
        .expect("a free port")
}

fn screenshots_dir() -> PathBuf {
    let dir = std::env::var_os("CONQUEST_SCREENSHOTS")
        .map(PathBuf::from)
        .unwrap_or_else(|| Path::new(env!("CARGO_TARGET_TMPDIR")).join("screenshots"));
    std::fs::create_dir_all(&dir).expect("screenshot dir");
    dir
}

/// How often, and how far apart, a read or click that raced a redraw is
/// tried again. The page redraws every 100 ms: retries 100 ms apart could
/// meet the redraw every time (a read lost to "stale element" ten times in
/// a row once), so they come at another pace.
const RETRIES: usize = 40;
const RETRY_PAUSE: Duration = Duration::from_millis(45);

/// The text the element shows (it must be displayed), tried again when it
/// races a redraw.
async fn text(c: &Client, css: &str) -> String {
    let mut last = String::new();
    for _ in 0..RETRIES {
        let e = match c.find(Locator::Css(css)).await {
            Ok(e) => e,
            Err(e) => {
                last = e.to_string();
                tokio::time::sleep(RETRY_PAUSE).await;
                continue;
            }
        };
        match (e.is_displayed().await, e.text().await) {
            (Ok(true), Ok(t)) => return t,
            (Ok(false), _) => last = format!("{css} is not on screen"),
            (Err(err), _) | (_, Err(err)) => last = err.to_string(),
        }
        tokio::time::sleep(RETRY_PAUSE).await;
    }
    panic!("{css}: {last}");
}

/// Waits until the JavaScript `expr` is truthy in the page.
async fn until(c: &Client, what: &str, limit: Duration, expr: &str) {
    let t0 = Instant::now();
    loop {
        let v = c
            .execute(&format!("return !!({expr});"), vec![])
            .await
            .unwrap_or(serde_json::Value::Bool(false));
        if v == serde_json::Value::Bool(true) {
            return;
        }
        if t0.elapsed() > limit {
            let status = text(c, "#status").await;
            panic!("timed out waiting for {what} (status {status})");
        }
        tokio::time::sleep(Duration::from_millis(100)).await;
    }
}

async fn js(c: &Client, expr: &str) -> serde_json::Value {
    c.execute(&format!("return {expr};"), vec![])
        .await
        .unwrap_or_else(|e| panic!("{expr}: {e}"))
}

async fn shoot(c: &Client, name: &str) {
    let png = c.screenshot().await.expect("screenshot");
    assert!(png.starts_with(b"\x89PNG"), "{name} is a PNG");
    std::fs::write(screenshots_dir().join(name), png).expect("write screenshot");
}

/// Clicks the element; tried again if a redraw replaced it in between.
async fn click(c: &Client, css: &str) {
    let mut last = String::new();
    for _ in 0..RETRIES {
        match c.find(Locator::Css(css)).await {
            Ok(e) => match e.click().await {
                Ok(_) => return,
                Err(err) => last = err.to_string(),
            },
            Err(err) => last = err.to_string(),
        }
        tokio::time::sleep(RETRY_PAUSE).await;
    }
    panic!("click {css}: {last}");
}

#[test]
fn the_page_runs_a_simulation_and_steers_a_robot_in_chromium() {
    if !Path::new(CHROMIUM).exists() || !Path::new(CHROMEDRIVER).exists() {
        assert!(
            std::env::var_os("CONQUEST_REQUIRE_BROWSER").is_none(),
            "CONQUEST_REQUIRE_BROWSER is set but {CHROMIUM} or {CHROMEDRIVER} is missing \
             (apt-get install chromium chromium-driver)"
        );
        eprintln!("SKIPPED: no {CHROMIUM} / {CHROMEDRIVER}; install chromium and chromium-driver");
        return;
    }
    let field = fields_dir().join("small/open-6x6.field");
    let field = field.to_string_lossy().into_owned();
    let server = Server::start(&["--field", &field, "--robots", "3", "--seed", "7"]);
    let port = free_port();
    let driver = Driver(
        Command::new(CHROMEDRIVER)
            .arg(format!("--port={port}"))
            .stdout(Stdio::null())
            .stderr(Stdio::null())
            .spawn()
            .expect("start chromedriver"),
    );
    let rt = tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
        .expect("runtime");
    rt.block_on(async {
        let c = connect(port).await;
        let result = drive(&c, server, &field).await;
        let _ = c.close().await;
        result
    });
    drop(driver);
}

async fn connect(port: u16) -> Client {
    let mut caps = serde_json::Map::new();
    caps.insert(
        "goog:chromeOptions".into(),
        serde_json::json!({
            "binary": CHROMIUM,
            "args": ["--headless=new", "--no-sandbox", "--disable-gpu", "--disable-dev-shm-usage",
                     "--no-first-run", "--disable-background-networking", "--window-size=1280,860",
                     "--hide-scrollbars"]
        }),
    );
    let connector = hyper_util::client::legacy::connect::HttpConnector::new();
    let t0 = Instant::now();
    loop {
        match ClientBuilder::new(connector.clone())
            .capabilities(caps.clone())
            .connect(&format!("http://127.0.0.1:{port}"))
            .await
        {
            Ok(c) => return c,
            Err(e) if t0.elapsed() < Duration::from_secs(20) => {
                let _ = e;
                tokio::time::sleep(Duration::from_millis(200)).await;
            }
            Err(e) => panic!("cannot reach chromedriver: {e}"),
        }
    }
}

async fn drive(c: &Client, server: Server, field: &str) {
    let minute = Duration::from_secs(60);
    c.goto(&server.url()).await.expect("load the page");
    until(
        c,
        "the snapshot",
        minute,
        "window.conquest.model.status === 'ready'",
    )
    .await;
    assert_eq!(text(c, "#status").await, "ready");
    assert_eq!(js(c, "window.conquest.model.robots.length").await, 3);
    shoot(c, "ready.png").await;

    // Start at 10× and photograph the map growing; then full speed until
    // the team is done.
    let rate = c.find(Locator::Css("#rate")).await.expect("rate");
    rate.select_by_value("10").await.expect("choose 10x");
    click(c, "#btn-start").await;
    until(
        c,
        "a third of the map",
        minute,
        "window.conquest.model.stats.known >= 12",
    )
    .await;
    shoot(c, "map-running.png").await;
    rate.select_by_value("0").await.expect("choose max");
    until(
        c,
        "the end of the run",
        minute * 2,
        "window.conquest.model.status === 'finished'",
    )
    .await;
    assert_eq!(text(c, "#status").await, "finished");
    // Let the map settle (robots drawn at home), then photograph it.
    tokio::time::sleep(Duration::from_millis(400)).await;
    shoot(c, "map.png").await;

    click(c, "#tab-stats").await;
    assert_eq!(text(c, "#stat-known").await, "36 / 36");
    assert_eq!(text(c, "#stat-coverage").await, "100 %");
    let result = text(c, "#stat-result").await;
    assert!(result.contains("complete"), "{result}");
    assert!(result.contains('×'), "makespan against the bound: {result}");
    let rows = c
        .find_all(Locator::Css("#robot-table tbody tr"))
        .await
        .expect("rows");
    assert_eq!(rows.len(), 3);
    // Robot 2 stands at home, (1, 0).
    let at = text(c, "#robot-table tr[data-robot='2'] td:nth-child(4)").await;
    assert!(at.starts_with("(1, 0)"), "{at}");
    shoot(c, "statistics.png").await;

    // Steer robot 2: take control, face east, drive one edge.
    click(c, "#tab-steer").await;
    click(c, "#robot-list button[data-robot='2']").await;
    click(c, "#btn-manual").await;
    until(
        c,
        "manual control",
        minute,
        "window.conquest.model.robots[2].state === 'manual'",
    )
    .await;
    let fwd = c.find(Locator::Id("btn-fwd")).await.expect("forward");
    for _ in 0..4 {
        if js(c, "window.conquest.model.robots[2].heading").await == 1 {
            break;
        }
        let h = js(c, "window.conquest.model.robots[2].heading").await;
        // The keyboard steers too: left arrow turns left.
        c.find(Locator::Css("body"))
            .await
            .expect("body")
            .send_keys(&Key::Left.to_string())
            .await
            .expect("key");
        until(
            c,
            "the turn",
            minute,
            &format!("window.conquest.model.robots[2].heading !== {h}"),
        )
        .await;
    }
    assert_eq!(js(c, "window.conquest.model.robots[2].heading").await, 1);
    until(
        c,
        "a free arm ahead",
        minute,
        "!document.getElementById('btn-fwd').disabled",
    )
    .await;
    fwd.click().await.expect("drive");
    until(
        c,
        "the move",
        minute,
        "window.conquest.model.robots[2].x === 2 && window.conquest.model.robots[2].y === 0",
    )
    .await;
    let info = text(c, "#steer-info").await;
    assert!(
        info.contains("(2, 0)") && info.contains("facing E"),
        "{info}"
    );
    shoot(c, "steer.png").await;
    click(c, "#btn-manual").await;
    until(
        c,
        "hand back",
        minute,
        "!window.conquest.model.robots[2].manual",
    )
    .await;

    // A phone-sized screen.
    c.set_window_size(390, 844).await.expect("phone size");
    click(c, "#tab-map").await;
    tokio::time::sleep(Duration::from_millis(300)).await;
    shoot(c, "phone-map.png").await;
    click(c, "#tab-steer").await;
    tokio::time::sleep(Duration::from_millis(300)).await;
    shoot(c, "phone-steer.png").await;
    c.set_window_size(1280, 860).await.expect("desktop size");

    // A robot's link is cut: the page says so, then sees it come back.
    click(c, "#robot-list button[data-robot='0']").await;
    click(c, "#btn-cut").await;
    until(
        c,
        "the link loss shown",
        minute,
        "!window.conquest.model.robots[0].link_up",
    )
    .await;
    let badge = text(c, "#robot-list button[data-robot='0']").await;
    assert!(badge.contains("link lost"), "{badge}");
    until(
        c,
        "the link back",
        minute,
        "window.conquest.model.robots[0].link_up",
    )
    .await;

    // The page's own connection: the server goes away and comes back.
    let port = server.port;
    drop(server);
    until(
        c,
        "the page to notice",
        minute,
        "document.getElementById('status').textContent === 'offline'",
    )
    .await;
    let banner = text(c, "#banner").await;
    assert!(banner.contains("reconnecting"), "{banner}");
    let again = Server::start_on(port, &["--field", field, "--robots", "2"]);
    until(
        c,
        "the reconnect",
        minute,
        "window.conquest.model.status === 'ready' && window.conquest.model.robots.length === 2",
    )
    .await;
    assert!(
        !c.find(Locator::Id("banner"))
            .await
            .expect("banner")
            .is_displayed()
            .await
            .expect("shown?")
    );
    drop(again);
}
