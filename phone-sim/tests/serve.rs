//! `conquest serve` over its HTTP API and WebSocket, as the page uses it:
//! a simulation runs to the end, a robot is steered by hand, bad requests
//! get clear errors, the map is exported and a field imported.

mod common;

use common::{Server, fields_dir};
use phone_sim::field;
use std::time::Duration;
use tungstenite::Message;

fn open6() -> String {
    fields_dir()
        .join("small/open-6x6.field")
        .to_string_lossy()
        .into_owned()
}

#[test]
fn the_page_and_its_assets_are_served_from_the_binary() {
    let s = Server::start(&[]);
    let (status, headers, body) = s.request("GET", "/", b"");
    assert_eq!(status, 200);
    assert!(headers.to_ascii_lowercase().contains("text/html"));
    let html = String::from_utf8(body).expect("utf-8");
    assert!(html.contains("e-puck Conquest"));
    // Nothing from the internet: every script and style is local.
    assert!(!html.contains("http://") && !html.contains("https://"));
    for (path, kind) in [("/app.js", "javascript"), ("/style.css", "text/css")] {
        let (status, headers, body) = s.request("GET", path, b"");
        assert_eq!(status, 200, "{path}");
        assert!(headers.to_ascii_lowercase().contains(kind), "{path}");
        assert!(body.len() > 1000, "{path}");
    }
    let (status, _, _) = s.request("GET", "/nothing-here", b"");
    assert_eq!(status, 404);
    // Ready, not running, before a person presses Start.
    let state = s.get_json("/api/state");
    assert_eq!(state["status"], "ready");
    assert_eq!(state["run"]["mode"], "sim");
    assert_eq!(state["robots"].as_array().map(Vec::len), Some(4));
    assert!(
        state["choices"]["strategies"]
            .as_array()
            .is_some_and(|a| a.iter().any(|s| s == "tempo"))
    );
}

#[test]
fn a_simulation_runs_to_the_end_then_a_robot_is_steered_by_hand() {
    let f = open6();
    let s = Server::start(&["--field", &f, "--robots", "3", "--seed", "7"]);
    assert_eq!(s.control(r#"{"type":"rate","x":0}"#).0, 200);
    assert_eq!(s.control(r#"{"type":"start"}"#).0, 200);
    let done = s.wait_for(Duration::from_secs(120), |st| st["status"] == "finished");
    assert_eq!(done["result"]["complete"], true, "{}", done["result"]);
    let truth = field::load(std::path::Path::new(&f)).expect("field");
    assert_eq!(done["stats"]["known"], truth.nodes().len());
    assert_eq!(done["stats"]["frontier"], 0);
    let makespan = done["result"]["makespan_s"].as_f64().expect("makespan");
    let bound = done["result"]["lower_bound_s"].as_f64().expect("bound");
    assert!(makespan >= bound && bound > 0.0, "{makespan} vs {bound}");
    assert!(done["coverage"].as_array().is_some_and(|c| !c.is_empty()));

    // The exported map is the true field.
    let (status, headers, body) = s.request("GET", "/api/export?format=field", b"");
    assert_eq!(status, 200);
    assert!(headers.contains("attachment"));
    let exported = field::native::parse(&String::from_utf8_lossy(&body), "export").expect("parses");
    assert_eq!(exported.nodes(), truth.nodes());

    // Steering: robot 2 stands at home (1, 0); east and north are free.
    let (status, e) = s.control(r#"{"type":"move","robot":2}"#);
    assert_eq!(status, 400);
    assert!(e["error"].as_str().is_some_and(|m| m.contains("manual")));
    assert_eq!(s.control(r#"{"type":"manual","robot":2,"on":true}"#).0, 200);
    let st = s.wait_for(Duration::from_secs(20), |st| {
        st["robots"][2]["state"] == "manual"
    });
    assert_eq!(st["robots"][2]["node"], serde_json::json!([1, 0]));
    let heading = st["robots"][2]["heading"].as_u64().expect("heading");
    // Face east (heading 1).
    let turn = match (1 + 4 - heading) % 4 {
        0 => None,
        1 => Some("right"),
        2 => Some("back"),
        _ => Some("left"),
    };
    if let Some(t) = turn {
        let cmd = format!(r#"{{"type":"turn","robot":2,"turn":"{t}"}}"#);
        assert_eq!(s.control(&cmd).0, 200);
        s.wait_for(Duration::from_secs(20), |st| {
            st["robots"][2]["heading"] == 1
        });
    }
    assert_eq!(s.control(r#"{"type":"move","robot":2}"#).0, 200);
    s.wait_for(Duration::from_secs(20), |st| {
        st["robots"][2]["node"] == serde_json::json!([2, 0]) && st["robots"][2]["x"] == 2.0
    });
    // Handed back, it goes home again and the team is done once more.
    assert_eq!(
        s.control(r#"{"type":"manual","robot":2,"on":false}"#).0,
        200
    );
    s.wait_for(Duration::from_secs(60), |st| {
        st["robots"][2]["node"] == serde_json::json!([1, 0]) && st["robots"][2]["state"] == "finish"
            || st["robots"][2]["state"] == "finished"
    });
    // Stop freezes the world; the result stays.
    assert_eq!(s.control(r#"{"type":"stop"}"#).0, 200);
    let a = s.get_json("/api/state");
    std::thread::sleep(Duration::from_millis(300));
    let b = s.get_json("/api/state");
    assert_eq!(b["status"], "stopped");
    assert_eq!(a["t_ms"], b["t_ms"]);
    assert_eq!(b["result"]["complete"], true);
}

#[test]
fn bad_requests_get_clear_errors_and_change_nothing() {
    let s = Server::start(&[]);
    for (cmd, needle) in [
        ("not json", "bad command"),
        (r#"{"type":"fly"}"#, "unknown variant"),
        (r#"{"type":"manual","robot":9,"on":true}"#, "no robot 9"),
        (
            r#"{"type":"speed","robot":0,"steps_per_s":5000}"#,
            "100..=1000",
        ),
        (r#"{"type":"rate","x":-1}"#, "rate"),
        (
            r#"{"type":"start","field":"no such field"}"#,
            "no field named",
        ),
        (
            r#"{"type":"start","strategy":"psychic"}"#,
            "unknown strategy",
        ),
    ] {
        let (status, e) = s.control(cmd);
        assert_eq!(status, 400, "{cmd}");
        let m = e["error"].as_str().unwrap_or_default();
        assert!(m.contains(needle), "{cmd}: {m}");
    }
    assert_eq!(s.get_json("/api/state")["status"], "ready");
    let (status, _, body) = s.request("GET", "/api/export?format=png", b"");
    assert_eq!(status, 400);
    assert!(String::from_utf8_lossy(&body).contains("field or sep"));
}

#[test]
fn an_imported_field_is_offered_and_a_broken_one_names_line_and_column() {
    let s = Server::start(&[]);
    let (status, _, body) = s.request(
        "POST",
        "/api/import?name=broken.field",
        b"conquest-field 1\nstart 0 0 N\nnode 0 0 NQ\n",
    );
    assert_eq!(status, 400);
    let e: serde_json::Value = serde_json::from_slice(&body).expect("json");
    assert!(
        e["error"]
            .as_str()
            .is_some_and(|m| m.starts_with("broken.field:3:10")),
        "{e}"
    );
    let text = std::fs::read(fields_dir().join("small/ring.sim")).expect("ring.sim");
    let (status, _, body) = s.request("POST", "/api/import?name=ring.sim", &text);
    assert_eq!(status, 200, "{}", String::from_utf8_lossy(&body));
    let choice: serde_json::Value = serde_json::from_slice(&body).expect("json");
    let name = choice["name"].as_str().expect("name").to_string();
    let state = s.get_json("/api/state");
    assert!(
        state["choices"]["fields"]
            .as_array()
            .is_some_and(|a| a.iter().any(|f| f["name"] == name.as_str()))
    );
    let cmd = serde_json::json!({"type": "start", "field": name, "robots": 1}).to_string();
    assert_eq!(s.control(&cmd).0, 200);
    let st = s.get_json("/api/state");
    assert_eq!(st["run"]["field"], name.as_str());
    assert_eq!(st["robots"].as_array().map(Vec::len), Some(1));
}

#[test]
fn the_websocket_sends_a_snapshot_then_frames_and_answers_errors() {
    let s = Server::start(&["--field", &open6(), "--robots", "2"]);
    let (mut ws, _) =
        tungstenite::connect(format!("ws://127.0.0.1:{}/ws", s.port)).expect("websocket");
    let read = |ws: &mut tungstenite::WebSocket<_>| -> serde_json::Value {
        loop {
            match ws.read().expect("read") {
                Message::Text(t) => return serde_json::from_str(t.as_str()).expect("json"),
                _ => continue,
            }
        }
    };
    let first = read(&mut ws);
    assert_eq!(first["type"], "snapshot");
    assert_eq!(first["run"]["robots"], 2);
    ws.send(Message::text(r#"{"type":"rate","x":0}"#))
        .expect("send");
    ws.send(Message::text(r#"{"type":"start","seed":3}"#))
        .expect("send");
    ws.send(Message::text(
        r#"{"type":"turn","robot":0,"turn":"sideways"}"#,
    ))
    .expect("send");
    let (mut snapshots, mut frames, mut errors, mut finished) = (0, 0, 0, false);
    for _ in 0..2000 {
        let m = read(&mut ws);
        match m["type"].as_str() {
            Some("snapshot") => snapshots += 1,
            Some("frame") => {
                frames += 1;
                assert!(m["robots"].as_array().is_some_and(|r| r.len() == 2));
                if m["status"] == "finished" {
                    finished = true;
                    break;
                }
            }
            Some("error") => {
                errors += 1;
                assert!(
                    m["message"]
                        .as_str()
                        .is_some_and(|t| t.contains("bad command"))
                );
            }
            other => panic!("unexpected push {other:?}"),
        }
    }
    assert!(finished, "no finished frame");
    assert_eq!(snapshots, 1, "Start sends one new snapshot");
    assert_eq!(errors, 1);
    assert!(frames >= 1);
}

/// Real robots: `serve --connect` drives a robot on a serial port (one end
/// of a pseudo-terminal pair; a robot-side link on the other end), shows
/// what it reports, and passes a person's commands on to it.
#[cfg(unix)]
#[test]
fn serve_connect_shows_a_real_robot_and_passes_commands_on() {
    use core_algo::geometry::Arms;
    use core_algo::protocol::message::{FirmwareVersion, RobotState, Status};
    use core_algo::protocol::{Event, Link, LinkConfig, MAX_FRAME_LEN, Message};
    use core_algo::team::RobotId;
    use serialport::SerialPort;
    use std::io::{Read, Write};
    use std::time::Instant;

    let (mut master, slave) = serialport::TTYPort::pair().expect("pty pair");
    let name = slave.name().expect("pty name");
    master
        .set_timeout(Duration::from_millis(5))
        .expect("timeout");
    let robot = std::thread::spawn(move || {
        let mut link = Link::new(LinkConfig::default(), RobotId(0), 0x2468_1357);
        link.send(Message::Hello {
            robot: RobotId(0),
            firmware: FirmwareVersion {
                major: 0,
                minor: 1,
                patch: 0,
            },
        })
        .expect("queue");
        let t0 = Instant::now();
        let (mut started, mut manual) = (None, false);
        let mut buf = [0u8; 256];
        let mut frame = [0u8; MAX_FRAME_LEN];
        while t0.elapsed() < Duration::from_secs(30) && !manual {
            let now = t0.elapsed().as_millis() as u32;
            if let Ok(n) = master.read(&mut buf) {
                link.on_bytes(now, &buf[..n]);
            }
            link.tick(now);
            while let Some(e) = link.poll_event() {
                match e {
                    Event::Received {
                        message: Message::Start { pose, .. },
                        ..
                    } => {
                        started = Some(pose);
                        link.send(Message::NodeHit {
                            pose,
                            arms: Arms::from_bits(0b0011),
                        })
                        .expect("queue");
                        link.send(Message::Status(Status {
                            uptime_ms: now,
                            pose,
                            state: RobotState::Stopped,
                            floor: 0,
                            proximity: 0,
                        }))
                        .expect("queue");
                    }
                    Event::Received {
                        message: Message::Manual { on: true },
                        ..
                    } => manual = true,
                    _ => {}
                }
            }
            while let Some(n) = link.poll_transmit(now, &mut frame) {
                master.write_all(&frame[..n]).expect("write");
            }
        }
        (started, manual)
    });
    let s = Server::start(&["--connect", &name, "--field", &open6()]);
    let st = s.wait_for(Duration::from_secs(20), |st| {
        st["robots"][0]["explored"] == 1 && st["robots"][0]["link_up"] == true
    });
    assert_eq!(st["run"]["mode"], "robots");
    assert_eq!(st["status"], "running");
    assert_eq!(st["robots"].as_array().map(Vec::len), Some(1));
    assert_eq!(st["robots"][0]["node"], serde_json::json!([0, 0]));
    assert_eq!(st["nodes"][0], serde_json::json!([0, 0, 3, 1]));
    // A new simulation makes no sense here; manual control does.
    let (status, e) = s.control(r#"{"type":"start"}"#);
    assert_eq!(status, 400, "{e}");
    assert_eq!(s.control(r#"{"type":"manual","robot":0,"on":true}"#).0, 200);
    let (started, manual) = robot.join().expect("robot thread");
    assert!(started.is_some(), "the robot was started");
    assert!(manual, "the robot heard the manual order");
}
