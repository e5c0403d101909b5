//! The keys the viewer reacts to, named the same way for the keyboard and for scripts.

use winit::keyboard::KeyCode;

#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Key {
    /// Fly forward, left, back, right, down, up.
    W,
    A,
    S,
    D,
    Q,
    E,
    /// Reset the accumulation.
    R,
    /// Save a PNG and an EXR of the current image.
    P,
    /// Next channel.
    C,
    /// Channel by position, 1-based.
    Digit(u8),
    Escape,
}

impl Key {
    /// A key by its script name: a letter, a digit 1-9 or `escape` (case ignored).
    pub fn parse(name: &str) -> Option<Key> {
        let lower = name.to_ascii_lowercase();
        Some(match lower.as_str() {
            "w" => Key::W,
            "a" => Key::A,
            "s" => Key::S,
            "d" => Key::D,
            "q" => Key::Q,
            "e" => Key::E,
            "r" => Key::R,
            "p" => Key::P,
            "c" => Key::C,
            "escape" | "esc" => Key::Escape,
            d if d.len() == 1 && ('1'..='9').contains(&d.chars().next()?) => {
                Key::Digit(d.as_bytes()[0] - b'0')
            }
            _ => return None,
        })
    }

    /// The key at a physical position (WASD stays WASD on any layout).
    pub fn from_code(code: KeyCode) -> Option<Key> {
        Some(match code {
            KeyCode::KeyW => Key::W,
            KeyCode::KeyA => Key::A,
            KeyCode::KeyS => Key::S,
            KeyCode::KeyD => Key::D,
            KeyCode::KeyQ => Key::Q,
            KeyCode::KeyE => Key::E,
            KeyCode::KeyR => Key::R,
            KeyCode::KeyP => Key::P,
            KeyCode::KeyC => Key::C,
            KeyCode::Escape => Key::Escape,
            KeyCode::Digit1 | KeyCode::Numpad1 => Key::Digit(1),
            KeyCode::Digit2 | KeyCode::Numpad2 => Key::Digit(2),
            KeyCode::Digit3 | KeyCode::Numpad3 => Key::Digit(3),
            KeyCode::Digit4 | KeyCode::Numpad4 => Key::Digit(4),
            KeyCode::Digit5 | KeyCode::Numpad5 => Key::Digit(5),
            KeyCode::Digit6 | KeyCode::Numpad6 => Key::Digit(6),
            KeyCode::Digit7 | KeyCode::Numpad7 => Key::Digit(7),
            KeyCode::Digit8 | KeyCode::Numpad8 => Key::Digit(8),
            KeyCode::Digit9 | KeyCode::Numpad9 => Key::Digit(9),
            _ => return None,
        })
    }

    /// Held down, these move the camera; the others act once per press.
    pub fn is_movement(self) -> bool {
        matches!(self, Key::W | Key::A | Key::S | Key::D | Key::Q | Key::E)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_case_blind_and_unknown_names_do_not() {
        assert_eq!(Key::parse("W"), Some(Key::W));
        assert_eq!(Key::parse("escape"), Some(Key::Escape));
        assert_eq!(Key::parse("3"), Some(Key::Digit(3)));
        assert_eq!(Key::parse("0"), None);
        assert_eq!(Key::parse("x"), None);
        assert_eq!(Key::parse("shift"), None);
    }
}
