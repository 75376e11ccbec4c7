//! e-puck2 firmware on RTIC 2.
//!
//! Tasks, highest priority first (each a few lines; the logic lives in the
//! drivers, `drivers-logic` and core-algo):
//!
//! | task | prio | kind | what |
//! |---|---|---|---|
//! | `left_step`, `right_step` | 6 | TIM4 / TIM3 interrupt | one half-step per timer update |
//! | `usart3` | 5 | USART3 interrupt | byte rings of the link |
//! | `sample` | 4 | 1 kHz | proximity schedule (ADC + emitters) |
//! | `control` | 3 | 100 Hz | ground read, sensor image, behaviour stack or calibration, motor command |
//! | `link` | 2 | on bytes | frames in, replies out (bootstrap protocol until core-algo's link layer) |
//! | `agent` | 1 | on events | decisions at nodes, owns the map |
//!
//! Selector 0 at power-on runs the ground-sensor calibration; any other
//! position runs. The `qemu` feature swaps the board for QEMU's
//! netduinoplus2 (see `board`).
#![no_std]
#![no_main]
#![deny(unsafe_code)]
#![deny(missing_docs)]
#![deny(warnings)]

mod board;
mod drivers;
mod robot;

use defmt_rtt as _;
#[cfg(not(feature = "qemu"))]
use panic_probe as _;
use rtic_monotonics::systick::prelude::*;

systick_monotonic!(Mono, 1_000);

/// Events queued from the control task to the agent (node reached, ...).
const AGENT_QUEUE: usize = 4;

#[rtic::app(device = stm32f4xx_hal::pac, peripherals = true, dispatchers = [SPI2, SPI3, UART4, UART5])]
mod app {
    use super::*;
    use crate::drivers::{
        config::{ConfigStore, MotorsStopped},
        leds::Leds,
        link::{LinkIsr, LinkTx, RX_CAPACITY, RxReceiver, TxQueue},
    };
    use crate::robot::{Agent, AgentEvent, Behaviour, MAP_BOUNDS, Map, MotorCommand, SensorImage};
    use core_algo::team::RobotId;
    use drivers_logic::{
        calibration::{CalibrationRun, Output},
        config::CalibrationRecord,
        frame::{FrameDecoder, FrameEvent, ParseError, Reply, Request, Status},
        ground::GroundCalibration,
        leds::arms_mask,
        selector::BootMode,
    };
    use heapless::spsc::Queue;
    use rtic_sync::{
        channel::{Receiver, Sender},
        make_channel,
    };
    use stm32f4xx_hal::serial::RxListen;

    #[shared]
    struct Shared {
        /// Both steppers: written by control and link, stepped by the timer interrupts.
        motors: board::Motors,
        /// Latest proximity values, from `sample`.
        prox: [u16; 8],
        /// Latest sensor image, from `control`.
        image: SensorImage,
        /// The behaviour stack (the link sets manual speeds in it).
        behaviour: Behaviour,
        /// The robot's known map (1024 nodes).
        map: Map,
    }

    #[local]
    struct Local {
        link_isr: LinkIsr,
        link_tx: LinkTx,
        rx_bytes: RxReceiver,
        prox_drv: board::Proximity,
        ground: board::Ground,
        leds: Leds,
        config: ConfigStore,
        mode: BootMode,
        selector: u8,
        to_agent: Sender<'static, AgentEvent, AGENT_QUEUE>,
        from_control: Receiver<'static, AgentEvent, AGENT_QUEUE>,
        robot: RobotId,
    }

    #[init(local = [tx_queue: TxQueue = Queue::new()])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let b = board::init(cx.device);
        Mono::start(cx.core.SYST, board::SYSCLK_HZ);

        // Enable reception before announcing readiness (QEMU drops bytes
        // that arrive earlier; the host waits for HELLO).
        let (tx, mut rx) = b.serial.split();
        rx.listen();
        let (rx_sender, rx_bytes) = make_channel!(u8, RX_CAPACITY);
        let (tx_prod, tx_cons) = cx.local.tx_queue.split();
        let (to_agent, from_control) = make_channel!(AgentEvent, AGENT_QUEUE);

        let map = Map::with_bounds(MAP_BOUNDS)
            .unwrap_or_else(|_| defmt::panic!("map bounds exceed 1024 nodes"));
        let mode = BootMode::from_selector(b.selector);
        defmt::info!(
            "boot: selector {}, mode {}, emulated {}",
            b.selector,
            mode,
            board::EMULATED
        );

        sample::spawn().ok();
        control::spawn().ok();
        link::spawn().ok();
        agent::spawn().ok();

        (
            Shared {
                motors: b.motors,
                prox: [0; 8],
                image: SensorImage::default(),
                behaviour: Behaviour::default(),
                map,
            },
            Local {
                link_isr: LinkIsr::new(rx, tx, rx_sender, tx_cons),
                link_tx: LinkTx::new(tx_prod),
                rx_bytes,
                prox_drv: b.prox,
                ground: b.ground,
                leds: b.leds,
                config: b.config,
                mode,
                selector: b.selector,
                to_agent,
                from_control,
                robot: RobotId(b.selector),
            },
        )
    }

    /// Left stepper: one half-step per TIM4 update.
    #[task(binds = TIM4, priority = 6, shared = [motors])]
    fn left_step(mut cx: left_step::Context) {
        cx.shared.motors.lock(|m| m.on_left_timer());
    }

    /// Right stepper: one half-step per TIM3 update.
    #[task(binds = TIM3, priority = 6, shared = [motors])]
    fn right_step(mut cx: right_step::Context) {
        cx.shared.motors.lock(|m| m.on_right_timer());
    }

    /// Link byte rings.
    #[task(binds = USART3, priority = 5, local = [link_isr])]
    fn usart3(cx: usart3::Context) {
        cx.local.link_isr.on_interrupt();
    }

    /// Proximity sampling, one schedule phase per millisecond.
    #[task(priority = 4, shared = [prox], local = [prox_drv])]
    async fn sample(mut cx: sample::Context) {
        let mut next = Mono::now();
        loop {
            cx.local.prox_drv.tick();
            let values = cx.local.prox_drv.values();
            cx.shared.prox.lock(|p| *p = values);
            next += 1.millis();
            Mono::delay_until(next).await;
        }
    }

    /// The 100 Hz control step.
    #[task(priority = 3, shared = [motors, prox, image, behaviour], local = [ground, leds, config, mode, to_agent])]
    async fn control(mut cx: control::Context) {
        let mut calibration = load_calibration(cx.local.config);
        let mut run = matches!(cx.local.mode, BootMode::Calibrate).then(CalibrationRun::new);
        let mut next = Mono::now();
        let mut cycle: u32 = 0;
        loop {
            let reading = cx.local.ground.read();
            let raw = reading.map(|r| r.delta).unwrap_or_default();
            let image = SensorImage {
                ground_raw: raw,
                ground: calibration.apply(raw),
                ground_ok: reading.is_some(),
                prox: cx.shared.prox.lock(|p| *p),
                steps: cx.shared.motors.lock(|m| m.steps()),
            };
            cx.shared.image.lock(|i| *i = image);

            let command = match run.as_mut() {
                Some(c) => match c.step(raw, (image.steps.0 + image.steps.1) / 2) {
                    Output::Drive(left, right) => MotorCommand { left, right },
                    Output::Store(record) => {
                        if let Some(c) =
                            store_calibration(&mut cx.shared.motors, cx.local.config, &record)
                        {
                            calibration = c;
                            cx.local.leds.set_ring(arms_mask(true, true, true, true));
                        }
                        run = None;
                        MotorCommand::default()
                    }
                    Output::Failed(e) => {
                        defmt::error!("calibration refused: {}", e);
                        cx.local.leds.set_front(true);
                        run = None;
                        MotorCommand::default()
                    }
                },
                None => {
                    let (command, event) = cx.shared.behaviour.lock(|b| b.step(&image));
                    if let Some(e) = event {
                        cx.local.to_agent.try_send(e).ok();
                    }
                    command
                }
            };
            cx.shared
                .motors
                .lock(|m| m.set_speeds(command.left, command.right));

            // Heartbeat: body LED toggles every 500 ms.
            cx.local.leds.set_body((cycle / 50).is_multiple_of(2));
            cycle = cycle.wrapping_add(1);
            next += 10.millis();
            Mono::delay_until(next).await;
        }
    }

    /// The stored ground calibration, or the identity map without one.
    fn load_calibration(config: &ConfigStore) -> GroundCalibration {
        match config.load() {
            Ok(r) => {
                GroundCalibration::new(r.black, r.white).unwrap_or(GroundCalibration::IDENTITY)
            }
            Err(e) => {
                defmt::warn!("no calibration record ({}), using identity", e);
                GroundCalibration::IDENTITY
            }
        }
    }

    /// Stops the motors and, once they stand still, writes the record to
    /// flash (the sector erase stalls the flash bus, steppers included).
    fn store_calibration(
        motors: &mut impl rtic::Mutex<T = board::Motors>,
        config: &mut ConfigStore,
        record: &CalibrationRecord,
    ) -> Option<GroundCalibration> {
        let proof = motors.lock(|m| {
            m.set_speeds(0, 0);
            MotorsStopped::checked(m.is_stopped())
        });
        match proof.map(|p| config.store(record, p)) {
            Some(Ok(())) => {
                defmt::info!("calibration stored: {}", record);
                GroundCalibration::new(record.black, record.white).ok()
            }
            Some(Err(e)) => {
                defmt::error!("calibration not stored: {}", e);
                None
            }
            None => {
                defmt::error!("calibration not stored: motors still running");
                None
            }
        }
    }

    /// The link: announce readiness, then answer frames.
    ///
    /// PLUG-IN(link): replace `FrameDecoder`/`Request`/`Reply` with
    /// core-algo's protocol and reliable link state machine; keep the rings.
    #[task(priority = 2, shared = [motors, image, behaviour, map], local = [link_tx, rx_bytes, selector, decoder: FrameDecoder = FrameDecoder::new()])]
    async fn link(mut cx: link::Context) {
        let selector = *cx.local.selector;
        let mode = if board::EMULATED {
            2
        } else if selector == 0 {
            0
        } else {
            1
        };
        send(
            cx.local.link_tx,
            Reply::Hello {
                robot: selector,
                mode,
            },
        );
        while let Ok(byte) = cx.local.rx_bytes.recv().await {
            let reply = match cx.local.decoder.push(byte) {
                None => continue,
                Some(FrameEvent::Dropped) => Reply::Error(ParseError::BadFrame),
                Some(FrameEvent::Frame(n)) => match Request::parse(cx.local.decoder.payload(n)) {
                    Err(e) => Reply::Error(e),
                    Ok(Request::Ping(seq)) => Reply::Pong(seq),
                    Ok(Request::Status) => {
                        let image = cx.shared.image.lock(|i| *i);
                        let steps = cx.shared.motors.lock(|m| m.steps());
                        let visited = cx.shared.map.lock(|m| m.visited_len()) as u16;
                        Reply::Status(Status {
                            selector,
                            left_steps: steps.0,
                            right_steps: steps.1,
                            visited,
                            capacity: MAP_BOUNDS.area() as u16,
                            ground_centre: image.ground[1],
                        })
                    }
                    Ok(Request::Speed(left, right)) => {
                        let applied = cx.shared.motors.lock(|m| m.set_speeds(left, right));
                        cx.shared.behaviour.lock(|b| {
                            b.manual = MotorCommand {
                                left: applied.0,
                                right: applied.1,
                            }
                        });
                        Reply::Speed(applied.0, applied.1)
                    }
                    Ok(Request::Visit { x, y, arms }) => {
                        let mut agent = Agent {
                            robot: RobotId(selector),
                        };
                        let (ok, visited) = cx.shared.map.lock(|m| {
                            let ok = agent.on_event(m, AgentEvent::Node { x, y, arms });
                            (ok, m.visited_len())
                        });
                        Reply::Visited(ok, visited as u16)
                    }
                    Ok(Request::Quit) if board::EMULATED => {
                        send(cx.local.link_tx, Reply::Bye);
                        while !cx.local.link_tx.is_idle() {
                            Mono::delay(1.millis()).await;
                        }
                        Mono::delay(5.millis()).await;
                        board::exit(true);
                    }
                    Ok(Request::Quit) => Reply::Error(ParseError::UnknownKind),
                },
            };
            send(cx.local.link_tx, reply);
        }
    }

    fn send(tx: &mut LinkTx, reply: Reply) {
        let mut payload = [0u8; drivers_logic::frame::MAX_PAYLOAD];
        let n = reply.encode(&mut payload);
        if !tx.send(&payload[..n]) {
            defmt::warn!("link: transmit ring full, reply dropped");
        }
    }

    /// The agent: decisions at nodes (lowest priority).
    #[task(priority = 1, shared = [map], local = [from_control, robot])]
    async fn agent(mut cx: agent::Context) {
        let mut agent = Agent {
            robot: *cx.local.robot,
        };
        while let Ok(event) = cx.local.from_control.recv().await {
            cx.shared.map.lock(|m| agent.on_event(m, event));
        }
    }
}
