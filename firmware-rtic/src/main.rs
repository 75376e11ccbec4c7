//! e-puck2 firmware on RTIC 2.
//!
//! Tasks, highest priority first (each a few lines; the logic lives in the
//! drivers, `drivers-logic` and core-algo):
//!
//! | task | prio | kind | what |
//! |---|---|---|---|
//! | `left_step`, `right_step` | 6 | TIM4 / TIM3 interrupt | one half-step per timer update |
//! | `usart3` (+ `usart2` emulated) | 5 | USART interrupt | byte rings of the link (and of the body channel) |
//! | `sample` | 4 | 1 kHz | proximity schedule (ADC + emitters) |
//! | `control` | 3 | 100 Hz | ground read, sensor image, behaviour stack or calibration, motor command |
//! | `link` (+ `body` emulated) | 2 | on bytes / 10 ms | core-algo's reliable link layer (the emulated board's body channel) |
//! | `agent` | 1 | on input / 50 ms | core-algo's agent and glue: decisions at nodes, owns the map |
//!
//! Selector 0 at power-on runs the ground-sensor calibration; any other
//! position N runs as robot N − 1. The `qemu` feature swaps the board for
//! QEMU's netduinoplus2 (see `board`).
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

/// Inputs queued for the agent (messages and body reports).
const AGENT_QUEUE: usize = 8;
/// Messages queued from the agent to the link.
const LINK_QUEUE: usize = 8;
/// Orders queued from the agent to the body.
const BODY_QUEUE: usize = 8;
/// Period of the link layer's timers.
const LINK_TICK_MS: u32 = 10;
/// Period of the agent's timers (timeouts, back-offs, keep-alives).
const AGENT_TICK_MS: u32 = 50;

/// Milliseconds since boot on the monotonic clock (wraps after 49 days;
/// core-algo compares times by wrapping difference).
fn now_ms() -> u32 {
    Mono::now().duration_since_epoch().as_millis()
}

#[rtic::app(device = stm32f4xx_hal::pac, peripherals = true, dispatchers = [SPI2, SPI3, UART4, UART5])]
mod app {
    use super::*;
    use crate::drivers::{
        config::{ConfigStore, MotorsStopped},
        leds::Leds,
        link::{LinkIsr, LinkTx, RX_CAPACITY, RxReceiver, TxQueue},
    };
    use crate::robot::{
        AgentInput, BodyCmd, FwAgent, LinkOut, MAP_BLOCKS, PLAN_CELLS, SensorImage,
        agent as make_agent, robot_id, timing_for,
    };
    use core_algo::agent::firmware::{Effect, Effects, Glue};
    use core_algo::map::Block;
    use core_algo::path::PlanCell;
    use core_algo::protocol::link::Event as LinkEvent;
    use core_algo::protocol::{Link, LinkConfig, MAX_FRAME_LEN, Message};
    use drivers_logic::{
        calibration::{CalibrationRun, Output},
        config::CalibrationRecord,
        leds::arms_mask,
        selector::BootMode,
    };
    use heapless::spsc::Queue;
    use rtic_sync::{
        channel::{Receiver, Sender},
        make_channel,
    };
    use stm32f4xx_hal::pac::{Interrupt, USART3};
    use stm32f4xx_hal::serial::RxListen;

    #[cfg(feature = "qemu")]
    use core_algo::agent::body::{BodyDecoder, BodyMsg};
    // Not behind `cfg`: RTIC's generated code names the types of the
    // emulated board's resources in both builds.
    use stm32f4xx_hal::pac::USART2;

    /// The emulated body channel's receive ring (bytes).
    const BODY_RX: usize = RX_CAPACITY;
    /// The host must say something on the body channel this often, or the
    /// emulated robot ends QEMU (no emulator outlives its host).
    #[cfg(feature = "qemu")]
    const HOST_SILENCE_MS: u32 = 10_000;

    /// Where the agent's orders go and the body's reports come from: the
    /// control task's behaviour stack, or the emulated board's body channel.
    pub struct BodyIo {
        cmds: Receiver<'static, BodyCmd, BODY_QUEUE>,
        to_agent: Sender<'static, AgentInput, AGENT_QUEUE>,
        /// A report the agent's queue had no room for yet.
        pending: Option<AgentInput>,
    }

    impl BodyIo {
        /// Hands `report` (and any earlier one still waiting) to the agent
        /// without blocking; keeps what does not fit for the next call.
        fn report(&mut self, report: Option<AgentInput>) {
            if let Some(r) = report
                && self.pending.replace(r).is_some()
            {
                defmt::warn!("agent queue full: report dropped");
            }
            if let Some(p) = self.pending.take()
                && let Err(rtic_sync::channel::TrySendError::Full(p)) = self.to_agent.try_send(p)
            {
                self.pending = Some(p);
            }
        }
    }

    #[shared]
    struct Shared {
        /// Both steppers: written by control, stepped by the timer interrupts.
        motors: board::Motors,
        /// Latest proximity values, from `sample`.
        prox: [u16; 8],
    }

    #[local]
    struct Local {
        link_isr: LinkIsr<USART3>,
        link_tx: LinkTx,
        rx_bytes: RxReceiver,
        link: Link,
        prox_drv: board::Proximity,
        ground: board::Ground,
        leds: Leds,
        config: ConfigStore,
        mode: BootMode,
        agent: FwAgent,
        glue: Glue,
        agent_in: Receiver<'static, AgentInput, AGENT_QUEUE>,
        link_to_agent: Sender<'static, AgentInput, AGENT_QUEUE>,
        to_link: Sender<'static, LinkOut, LINK_QUEUE>,
        from_agent: Receiver<'static, LinkOut, LINK_QUEUE>,
        to_body: Sender<'static, BodyCmd, BODY_QUEUE>,
        /// The behaviour stack's end of the body queues (real board only).
        behaviour_io: Option<BodyIo>,
        /// The emulated body channel's end of the body queues.
        #[cfg(feature = "qemu")]
        body_io: BodyIo,
        #[cfg(feature = "qemu")]
        body_isr: LinkIsr<USART2>,
        #[cfg(feature = "qemu")]
        body_tx: LinkTx,
        #[cfg(feature = "qemu")]
        body_rx: Receiver<'static, u8, BODY_RX>,
    }

    #[init(local = [
        tx_queue: TxQueue = Queue::new(),
        body_queue: Queue<u8, 64> = Queue::new(),
        blocks: [Block; MAP_BLOCKS] = [Block::ZEROED; MAP_BLOCKS],
        cells: [PlanCell; PLAN_CELLS] = [PlanCell::ZEROED; PLAN_CELLS],
    ])]
    fn init(cx: init::Context) -> (Shared, Local) {
        let b = board::init(cx.device);
        Mono::start(cx.core.SYST, board::SYSCLK_HZ);
        // The cycle counter times the control step on the robot (QEMU does
        // not model the DWT; the emulated build measures with `bench=N`).
        #[cfg(not(feature = "qemu"))]
        {
            let (mut dcb, mut dwt) = (cx.core.DCB, cx.core.DWT);
            dcb.enable_trace();
            dwt.enable_cycle_counter();
        }

        // Enable reception before announcing readiness (QEMU drops bytes
        // that arrive earlier; the host waits for the link's first frame).
        let (tx, mut rx) = b.serial.split();
        rx.listen();
        let (rx_sender, rx_bytes) = make_channel!(u8, RX_CAPACITY);
        let (tx_prod, tx_cons) = cx.local.tx_queue.split();
        let (link_to_agent, agent_in) = make_channel!(AgentInput, AGENT_QUEUE);
        let (to_link, from_agent) = make_channel!(LinkOut, LINK_QUEUE);
        let (to_body, body_cmds) = make_channel!(BodyCmd, BODY_QUEUE);
        let io = BodyIo {
            cmds: body_cmds,
            to_agent: link_to_agent.clone(),
            pending: None,
        };
        #[cfg(feature = "qemu")]
        let (behaviour_io, body_io) = (None, io);
        #[cfg(not(feature = "qemu"))]
        let behaviour_io = Some(io);

        let mode = BootMode::from_selector(b.selector);
        let id = robot_id(b.selector);
        defmt::info!(
            "boot: selector {}, mode {}, robot {}, emulated {}",
            b.selector,
            mode,
            id.0,
            board::EMULATED
        );

        #[cfg(feature = "qemu")]
        let (body_isr, body_tx, body_rx) = {
            let (tx, mut rx) = b.body_serial.split();
            rx.listen();
            let (sender, receiver) = make_channel!(u8, BODY_RX);
            let (prod, cons) = cx.local.body_queue.split();
            (
                LinkIsr::new(rx, tx, sender, cons),
                LinkTx::new(prod, Interrupt::USART2),
                receiver,
            )
        };
        #[cfg(not(feature = "qemu"))]
        let _ = &cx.local.body_queue;

        sample::spawn().ok();
        control::spawn().ok();
        link::spawn().ok();
        agent::spawn().ok();
        #[cfg(feature = "qemu")]
        body::spawn().ok();

        (
            Shared {
                motors: b.motors,
                prox: [0; 8],
            },
            Local {
                link_isr: LinkIsr::new(rx, tx, rx_sender, tx_cons),
                link_tx: LinkTx::new(tx_prod, Interrupt::USART3),
                rx_bytes,
                link: Link::new(LinkConfig::default(), id, b.nonce),
                prox_drv: b.prox,
                ground: b.ground,
                leds: b.leds,
                config: b.config,
                mode,
                agent: make_agent(id, cx.local.blocks, cx.local.cells),
                glue: Glue::new(id),
                agent_in,
                link_to_agent,
                to_link,
                from_agent,
                to_body,
                behaviour_io,
                #[cfg(feature = "qemu")]
                body_io,
                #[cfg(feature = "qemu")]
                body_isr,
                #[cfg(feature = "qemu")]
                body_tx,
                #[cfg(feature = "qemu")]
                body_rx,
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

    /// Body channel byte rings (emulated board).
    #[cfg(feature = "qemu")]
    #[task(binds = USART2, priority = 5, local = [body_isr])]
    fn usart2(cx: usart2::Context) {
        cx.local.body_isr.on_interrupt();
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

    /// The 100 Hz control step: the behaviour stack carries out the agent's
    /// orders and reports back (the emulated board's body is on the host,
    /// so there it only keeps the sensor image and the heartbeat).
    #[task(priority = 3, shared = [motors, prox], local = [ground, leds, config, mode, behaviour_io])]
    async fn control(mut cx: control::Context) {
        #[cfg(feature = "qemu")]
        if let Some(n) = board::bench_steps() {
            let (ms, moving) = crate::robot::bench(n);
            cortex_m_semihosting::hprintln!(
                "bench: {} behaviour steps in {} ms of emulated time, still following the line: {}",
                n,
                ms,
                moving
            );
            board::exit(true);
        }
        let record = load_record(cx.local.config);
        let mut run = matches!(cx.local.mode, BootMode::Calibrate).then(CalibrationRun::new);
        let (black, white) = record.map_or(([0; 3], [0; 3]), |r| (r.black, r.white));
        let mut body = crate::robot::behaviour(black, white);
        let mut worst: u32 = 0;
        let mut next = Mono::now();
        let mut cycle: u32 = 0;
        loop {
            let reading = cx.local.ground.read();
            let image = SensorImage {
                ground_raw: reading.map(|r| r.delta).unwrap_or_default(),
                ground_ok: reading.is_some(),
                prox: cx.shared.prox.lock(|p| *p),
                steps: cx.shared.motors.lock(|m| m.steps()),
            };
            let (left, right) = match run.as_mut() {
                Some(c) => match c.step(image.ground_raw, (image.steps.0 + image.steps.1) / 2) {
                    Output::Drive(left, right) => (left, right),
                    Output::Store(record) => {
                        if store_calibration(&mut cx.shared.motors, cx.local.config, &record) {
                            body = crate::robot::behaviour(record.black, record.white);
                            cx.local.leds.set_ring(arms_mask(true, true, true, true));
                        }
                        run = None;
                        (0, 0)
                    }
                    Output::Failed(e) => {
                        defmt::error!("calibration refused: {}", e);
                        cx.local.leds.set_front(true);
                        run = None;
                        (0, 0)
                    }
                },
                None => match cx.local.behaviour_io.as_mut() {
                    Some(io) => {
                        while let Ok(cmd) = io.cmds.try_recv() {
                            let refused = match cmd {
                                BodyCmd::Order(o) => body.order(o).is_err(),
                                BodyCmd::Speed(v) => {
                                    let v = i16::try_from(v.min(1000)).unwrap_or(1000).max(1);
                                    body.robot_mut()
                                        .order(core_algo::behaviour::Command::SetSpeed(v))
                                        .is_err()
                                }
                            };
                            if refused {
                                defmt::warn!("behaviour refused {}", defmt::Debug2Format(&cmd));
                            }
                        }
                        let c0 = cortex_m::peripheral::DWT::cycle_count();
                        let (wheels, report) = body.step(&image.sensors());
                        let cycles = cortex_m::peripheral::DWT::cycle_count().wrapping_sub(c0);
                        worst = worst.max(cycles);
                        if cycle.is_multiple_of(1000) {
                            defmt::info!("behaviour step: {} cycles, worst {}", cycles, worst);
                        }
                        io.report(report.map(AgentInput::Report));
                        (wheels.left, wheels.right)
                    }
                    // The emulated board: the host's simulated body carries
                    // out the orders (`body` task).
                    None => (0, 0),
                },
            };
            cx.shared.motors.lock(|m| m.set_speeds(left, right));

            // Heartbeat: body LED toggles every 500 ms.
            cx.local.leds.set_body((cycle / 50).is_multiple_of(2));
            cycle = cycle.wrapping_add(1);
            next += 10.millis();
            Mono::delay_until(next).await;
        }
    }

    /// The stored ground calibration record, if there is a valid one.
    fn load_record(config: &ConfigStore) -> Option<CalibrationRecord> {
        match config.load() {
            Ok(r) => Some(r),
            Err(e) => {
                defmt::warn!("no calibration record ({}): floor orders refused", e);
                None
            }
        }
    }

    /// Stops the motors and, once they stand still, writes the record to
    /// flash (the sector erase stalls the flash bus, steppers included).
    fn store_calibration(
        motors: &mut impl rtic::Mutex<T = board::Motors>,
        config: &mut ConfigStore,
        record: &CalibrationRecord,
    ) -> bool {
        let proof = motors.lock(|m| {
            m.set_speeds(0, 0);
            MotorsStopped::checked(m.is_stopped())
        });
        match proof.map(|p| config.store(record, p)) {
            Some(Ok(())) => {
                defmt::info!("calibration stored: {}", record);
                true
            }
            Some(Err(e)) => {
                defmt::error!("calibration not stored: {}", e);
                false
            }
            None => {
                defmt::error!("calibration not stored: motors still running");
                false
            }
        }
    }

    /// The link layer: core-algo's reliable link over the USART3 rings.
    /// Received messages go to the agent, the agent's messages to the
    /// phone; the timers run every 10 ms. The link's first frame (a Sync)
    /// announces readiness.
    #[task(priority = 2, local = [link, link_tx, rx_bytes, link_to_agent, from_agent])]
    async fn link(cx: link::Context) {
        let link = cx.local.link;
        let mut pending: Option<LinkOut> = None;
        let mut frame = [0u8; MAX_FRAME_LEN];
        let mut next = Mono::now();
        loop {
            if let Ok(received) = Mono::timeout_at(next, cx.local.rx_bytes.recv()).await {
                let Ok(byte) = received else {
                    defmt::error!("link: receive ring closed");
                    return;
                };
                let now = now_ms();
                link.on_bytes(now, &[byte]);
                while let Ok(b) = cx.local.rx_bytes.try_recv() {
                    link.on_bytes(now, &[b]);
                }
            }
            let now = now_ms();
            if Mono::now() >= next {
                link.tick(now);
                next += LINK_TICK_MS.millis();
                if Mono::now() > next {
                    // Fell behind (a long interrupt burst): skip, no catch-up.
                    next = Mono::now() + LINK_TICK_MS.millis();
                }
            }
            // The agent's messages, as far as the window has room.
            loop {
                let Some(out) = pending
                    .take()
                    .or_else(|| cx.local.from_agent.try_recv().ok())
                else {
                    break;
                };
                match out {
                    LinkOut::Reliable(m) if link.can_send() => {
                        let _ = link.send(m);
                    }
                    LinkOut::Reliable(m) => {
                        pending = Some(LinkOut::Reliable(m));
                        break;
                    }
                    LinkOut::Datagram(m) => link.send_datagram(m),
                }
            }
            // Received messages, as far as the agent's queue has room (the
            // link holds the rest and acknowledges them later).
            while !cx.local.link_to_agent.is_full() {
                match link.poll_event() {
                    Some(LinkEvent::Received { message, .. }) => {
                        let _ = cx
                            .local
                            .link_to_agent
                            .try_send(AgentInput::Message(message));
                    }
                    Some(LinkEvent::LinkUp) => defmt::info!("link: up"),
                    Some(LinkEvent::LinkLost) => defmt::warn!("link: lost"),
                    Some(LinkEvent::PeerRestarted) => defmt::info!("link: phone restarted"),
                    None => break,
                }
            }
            while cx.local.link_tx.room() >= MAX_FRAME_LEN {
                let Some(n) = link.poll_transmit(now, &mut frame) else {
                    break;
                };
                cx.local.link_tx.send(frame.get(..n).unwrap_or(&[]));
            }
        }
    }

    /// The emulated board's body channel: the agent's orders out to the
    /// host's simulated body, its reports in (see `BodyMsg`). Ends QEMU on
    /// the host's `Q`, or when the host has been silent too long.
    #[cfg(feature = "qemu")]
    #[task(priority = 2, local = [body_tx, body_rx, body_io])]
    async fn body(cx: body::Context) {
        let io = cx.local.body_io;
        send_line(cx.local.body_tx, BodyMsg::Hello);
        let mut decoder = BodyDecoder::new();
        let mut heard = now_ms();
        loop {
            let mut report = None;
            if let Ok(Ok(byte)) = Mono::timeout_after(20.millis(), cx.local.body_rx.recv()).await {
                match decoder.push(byte) {
                    Some(BodyMsg::Report(r)) => {
                        heard = now_ms();
                        report = Some(AgentInput::Report(r));
                    }
                    Some(BodyMsg::KeepAlive) => heard = now_ms(),
                    Some(BodyMsg::Quit) => {
                        while !cx.local.body_tx.is_idle() {
                            Mono::delay(1.millis()).await;
                        }
                        board::exit(true);
                    }
                    Some(other) => defmt::warn!("body: unexpected {}", defmt::Debug2Format(&other)),
                    None => {}
                }
            }
            io.report(report);
            if now_ms().wrapping_sub(heard) > HOST_SILENCE_MS {
                defmt::error!("body: host silent, ending the emulation");
                board::exit(false);
            }
            while let Ok(cmd) = io.cmds.try_recv() {
                if let BodyCmd::Order(o) = cmd {
                    send_line(cx.local.body_tx, BodyMsg::Order(o));
                }
            }
        }
    }

    /// Queues one body-channel line.
    #[cfg(feature = "qemu")]
    fn send_line(tx: &mut LinkTx, msg: BodyMsg) {
        let (buf, n) = msg.encode();
        if !tx.send(buf.get(..n).unwrap_or(&[])) {
            defmt::warn!("body: transmit ring full, line dropped");
        }
    }

    /// The agent: core-algo's agent and the firmware glue, at the lowest
    /// priority (a decision plans over the whole map). Every input and
    /// every 50 ms tick may produce orders for the body and messages for
    /// the phone.
    #[task(priority = 1, local = [agent, glue, agent_in, to_link, to_body])]
    async fn agent(cx: agent::Context) {
        let (agent, glue) = (cx.local.agent, cx.local.glue);
        let _ = cx.local.to_link.send(LinkOut::Reliable(glue.hello())).await;
        let mut next = Mono::now() + AGENT_TICK_MS.millis();
        loop {
            let input = Mono::timeout_at(next, cx.local.agent_in.recv()).await;
            let now = now_ms();
            let mut out = Effects::new();
            match input {
                Ok(Ok(AgentInput::Message(m))) => {
                    if let Message::Start { settings, .. } = &m {
                        agent.set_timing(timing_for(settings.speed));
                        let _ = cx.local.to_body.send(BodyCmd::Speed(settings.speed)).await;
                    }
                    glue.on_message(agent, now, &m, &mut out);
                }
                Ok(Ok(AgentInput::Report(r))) => glue.on_report(agent, now, r, &mut out),
                Ok(Err(_)) => {
                    defmt::error!("agent: input queue closed");
                    return;
                }
                Err(_) => {}
            }
            carry_out(cx.local.to_link, cx.local.to_body, out).await;
            if Mono::now() >= next {
                let mut out = Effects::new();
                glue.tick(agent, now, &mut out);
                carry_out(cx.local.to_link, cx.local.to_body, out).await;
                next += AGENT_TICK_MS.millis();
                if Mono::now() > next {
                    next = Mono::now() + AGENT_TICK_MS.millis();
                }
            }
        }
    }

    /// Hands the glue's effects to the link and the body. Waits when a
    /// queue is full: their consumers never wait for the agent.
    async fn carry_out(
        to_link: &mut Sender<'static, LinkOut, LINK_QUEUE>,
        to_body: &mut Sender<'static, BodyCmd, BODY_QUEUE>,
        effects: Effects,
    ) {
        for e in effects {
            let _ = match e {
                Effect::Body(o) => to_body.send(BodyCmd::Order(o)).await.map_err(|_| ()),
                Effect::Send(m) => to_link.send(LinkOut::Reliable(m)).await.map_err(|_| ()),
                Effect::Datagram(m) => to_link.send(LinkOut::Datagram(m)).await.map_err(|_| ()),
            };
        }
    }
}
