//! Unit tests of the scene reader's internals: the key index (span -> key path), the
//! translation of toml/serde messages, and the `end` -> steps rule. Expected values are
//! read off the literal documents below.

use super::*;

fn index(source: &str) -> KeyIndex {
    let (root, errors) = DeTable::parse_recoverable(source);
    assert!(errors.is_empty(), "test document must be valid TOML");
    KeyIndex::new(root.get_ref())
}

/// Path of the innermost key around the first occurrence of `needle` in `source`.
fn path_at(keys: &KeyIndex, source: &str, needle: &str) -> Option<String> {
    let start = source.find(needle)?;
    keys.innermost(&(start..start + needle.len())).map(|e| e.path.clone())
}

#[test]
fn key_paths_follow_tables_arrays_and_dotted_keys() {
    let s = "[time]\nstep = 0.5\n[[body]]\nname = 'a'\n[[body]]\nname = 'b'\n\
             vertices = [[0, 1], [2, 3]]\nx.y = 7\n";
    let keys = index(s);
    assert_eq!(path_at(&keys, s, "0.5").as_deref(), Some("time.step"));
    assert_eq!(path_at(&keys, s, "'b'").as_deref(), Some("body[1].name"));
    assert_eq!(path_at(&keys, s, "3").as_deref(), Some("body[1].vertices[1][1]"));
    assert_eq!(path_at(&keys, s, "[[0, 1], [2, 3]]").as_deref(), Some("body[1].vertices"));
    assert_eq!(path_at(&keys, s, "7").as_deref(), Some("body[1].x.y"));
    // an array of tables and its first element share the first header: the element wins
    assert_eq!(path_at(&keys, s, "[[body]]").as_deref(), Some("body[0]"));
    assert!(keys.innermost(&(0..0)).is_none(), "an empty span names no key");
}

#[test]
fn a_value_error_points_at_the_whole_key_value_pair() {
    let s = "[time]\n  step = -1\n";
    let start = s.find("-1").unwrap_or_default();
    let e = Problem::new(start..start + 2, "step must be positive").into_error(s, "f");
    assert_eq!((e.line, e.column, e.key.as_str()), (2, 3, "time.step"));
}

#[test]
fn a_missing_key_extends_the_table_path() {
    let s = "[time]\nstep = 1.0\n";
    let e = Problem::missing(0..6, "steps", "needs steps").into_error(s, "f");
    assert_eq!((e.line, e.key.as_str()), (1, "time.steps"));
}

#[test]
fn serde_messages_speak_of_keys_arrays_and_numbers() {
    let s = "[time]\nstep = 'x'\nstepz = 1\n";
    let Err(e) = toml::from_str::<raw::Time>("step = 'x'") else { panic!("a string is not a number") };
    assert_eq!(Problem::from_toml(&e, s).message, "invalid type: string \"x\", expected a number");
    let Err(e) = toml::from_str::<raw::Time>("steps = 1") else { panic!("step is required") };
    let p = Problem::from_toml(&e, s);
    assert_eq!((p.message.as_str(), p.missing.as_deref()), ("missing key `step`", Some("step")));
}

#[test]
fn end_rounds_up_to_whole_steps_but_not_for_round_off() {
    assert_eq!(steps_for(1.0, 0.1), Some(10));
    assert_eq!(steps_for(0.07, 0.01), Some(7), "0.07 / 0.01 = 7.000000000000001");
    assert_eq!(steps_for(0.3, 0.1), Some(3), "0.3 / 0.1 = 2.9999999999999996");
    assert_eq!(steps_for(0.25, 0.1), Some(3));
    assert_eq!(steps_for(1e-12, 1.0), None);
}

/// `time.steps` of a minimal scene with `end` and `step`; None if rejected.
fn steps_for(end: f64, step: f64) -> Option<usize> {
    let s = format!(
        "[scene]\nname='t'\n[time]\nstep={step:e}\nend={end:e}\n[[material]]\n\
                     name='m'\ndensity=1\n[[body]]\nname='b'\nshape='disk'\ncenter=[0,0]\n\
                     radius=1\nmaterial='m'\n"
    );
    parse(&s, "f").ok().map(|m| m.time.steps)
}
