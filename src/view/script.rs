//! Scripted input for the viewer (`--script FILE`), so a test can drive it like a user without
//! a tool that fakes X events. One event per line; `#` starts a comment:
//!
//! ```text
//! wait 4              # render 4 frames before the next event
//! key c               # press and release a key (names: w a s d q e r p c 1-9 escape)
//! hold w 3            # hold a key down for 3 frames (movement)
//! drag 40 -10         # drag the mouse with the left button by (dx, dy) pixels
//! scroll 2            # scroll 2 lines (speed)
//! screenshot out.png  # write what the window shows, as PNG
//! quit
//! ```
//!
//! Events between two `wait`s happen in the same frame, before it is rendered; a `screenshot`
//! is taken after that frame is shown and ends the frame's events (the next event happens in
//! the next frame), so the script reads in time order.

use super::keys::Key;
use glam::Vec2;
use std::path::{Path, PathBuf};

#[derive(Clone, Debug, PartialEq)]
pub enum ScriptEvent {
    Wait(u32),
    Key(Key),
    Hold(Key, u32),
    Drag(Vec2),
    Scroll(f32),
    Screenshot(PathBuf),
    Quit,
}

/// A parsed script being played, frame by frame.
#[derive(Debug)]
pub struct Script {
    events: Vec<ScriptEvent>,
    next: usize,
    /// Frames still to wait before `events[next]`.
    waiting: u32,
    /// Held keys and the frames they stay down.
    holds: Vec<(Key, u32)>,
}

/// What the script does in one frame.
#[derive(Debug, Default, PartialEq)]
pub struct ScriptFrame {
    pub taps: Vec<Key>,
    pub held: Vec<Key>,
    pub drag: Vec2,
    pub scroll: f32,
    pub screenshots: Vec<PathBuf>,
    pub quit: bool,
}

impl Script {
    pub fn load(path: &Path) -> Result<Script, String> {
        let text = crate::text_file::read_utf8(path)
            .map_err(|e| format!("{}: cannot read the script: {e}", path.display()))?;
        Script::parse(&text)
            .map_err(|(line, message)| format!("{}:{line}: {message}", path.display()))
    }

    /// Errors carry the 1-based line.
    pub fn parse(text: &str) -> Result<Script, (usize, String)> {
        let mut events = Vec::new();
        for (i, raw) in text.lines().enumerate() {
            let line = raw.split('#').next().unwrap_or("").trim();
            if line.is_empty() {
                continue;
            }
            events.push(parse_event(line).map_err(|m| (i + 1, m))?);
        }
        Ok(Script {
            events,
            next: 0,
            waiting: 0,
            holds: Vec::new(),
        })
    }

    /// True once every event has happened and no key is held.
    pub fn finished(&self) -> bool {
        self.next >= self.events.len() && self.holds.is_empty()
    }

    /// Advances one frame: the events due now, and the keys held during it.
    pub fn frame(&mut self) -> ScriptFrame {
        let mut out = ScriptFrame::default();
        if self.waiting > 0 {
            self.waiting -= 1;
        } else {
            while let Some(event) = self.events.get(self.next) {
                self.next += 1;
                match event {
                    ScriptEvent::Wait(n) => {
                        // This frame is the first of the wait.
                        self.waiting = n.saturating_sub(1);
                        break;
                    }
                    ScriptEvent::Key(k) => out.taps.push(*k),
                    ScriptEvent::Hold(k, n) => self.holds.push((*k, *n)),
                    ScriptEvent::Drag(d) => out.drag += *d,
                    ScriptEvent::Scroll(s) => out.scroll += *s,
                    ScriptEvent::Screenshot(p) => {
                        // Taken once this frame is shown; later events belong to the next
                        // frame, so `screenshot a.png` then `key 2` shots the old channel.
                        out.screenshots.push(p.clone());
                        break;
                    }
                    ScriptEvent::Quit => {
                        out.quit = true;
                        break;
                    }
                }
            }
        }
        out.held = self.holds.iter().map(|(k, _)| *k).collect();
        self.holds.retain_mut(|(_, frames)| {
            *frames = frames.saturating_sub(1);
            *frames > 0
        });
        out
    }
}

fn parse_event(line: &str) -> Result<ScriptEvent, String> {
    let mut words = line.split_whitespace();
    let verb = words.next().unwrap_or("");
    let args: Vec<&str> = words.collect();
    let want = |n: usize, usage: &str| {
        if args.len() == n {
            Ok(())
        } else {
            Err(format!("'{verb}' takes {usage}, got '{line}'"))
        }
    };
    let frames = |s: &str| {
        s.parse::<u32>()
            .map_err(|_| format!("'{s}' is not a frame count (a whole number)"))
    };
    let number = |s: &str| match s.parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("'{s}' is not a number")),
    };
    let key = |s: &str| {
        Key::parse(s)
            .ok_or_else(|| format!("unknown key '{s}' (keys: w a s d q e r p c 1-9 escape)"))
    };
    match verb {
        "wait" => {
            want(1, "a frame count")?;
            Ok(ScriptEvent::Wait(frames(args[0])?))
        }
        "key" => {
            want(1, "a key name")?;
            Ok(ScriptEvent::Key(key(args[0])?))
        }
        "hold" => {
            want(2, "a key name and a frame count")?;
            Ok(ScriptEvent::Hold(key(args[0])?, frames(args[1])?))
        }
        "drag" => {
            want(2, "dx and dy in pixels")?;
            Ok(ScriptEvent::Drag(Vec2::new(
                number(args[0])?,
                number(args[1])?,
            )))
        }
        "scroll" => {
            want(1, "a number of lines")?;
            Ok(ScriptEvent::Scroll(number(args[0])?))
        }
        "screenshot" => {
            // The rest of the line, so a path may contain spaces.
            let path = line["screenshot".len()..].trim();
            if path.is_empty() {
                return Err("'screenshot' takes a .png path".into());
            }
            if !path.to_ascii_lowercase().ends_with(".png") {
                return Err(format!("screenshot '{path}': the path must end in .png"));
            }
            Ok(ScriptEvent::Screenshot(PathBuf::from(path)))
        }
        "quit" => {
            want(0, "nothing")?;
            Ok(ScriptEvent::Quit)
        }
        other => Err(format!(
            "unknown event '{other}' (events: wait, key, hold, drag, scroll, screenshot, quit)"
        )),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn events_happen_in_the_frame_after_their_wait() {
        let mut s = Script::parse(
            "# start\nwait 2\nkey c\ndrag 3 -4 # look\nwait 1\nscreenshot a b.png\nquit\n",
        )
        .unwrap();
        assert_eq!(s.frame(), ScriptFrame::default());
        assert_eq!(s.frame(), ScriptFrame::default());
        let third = s.frame();
        assert_eq!(third.taps, vec![Key::C]);
        assert_eq!(third.drag, Vec2::new(3.0, -4.0));
        let fourth = s.frame();
        assert_eq!(fourth.screenshots, vec![PathBuf::from("a b.png")]);
        assert!(!fourth.quit);
        assert!(s.frame().quit);
        assert!(s.finished());
    }

    #[test]
    fn a_held_key_stays_down_for_its_frames() {
        let mut s = Script::parse("hold w 2\nwait 5").unwrap();
        assert_eq!(s.frame().held, vec![Key::W]);
        assert_eq!(s.frame().held, vec![Key::W]);
        assert_eq!(s.frame().held, Vec::<Key>::new());
    }

    #[test]
    fn errors_name_the_line() {
        let err = |t: &str| Script::parse(t).unwrap_err();
        assert_eq!(err("wait 1\nkey shift").0, 2);
        assert!(err("key shift").1.contains("unknown key 'shift'"));
        assert!(err("jump 3").1.contains("unknown event 'jump'"));
        assert!(err("wait -1").1.contains("frame count"));
        assert!(err("drag 1").1.contains("dx and dy"));
        assert!(err("screenshot x.jpg").1.contains(".png"));
        assert!(err("\n\nquit now").0 == 3);
    }
}
