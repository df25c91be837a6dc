//! Pre-processing of the raw argument list so that joint values may start with a hyphen.
//!
//! Clap's `allow_negative_numbers` accepts `-90` and `-45.5` as values but rejects tokens
//! such as `-.5`, `-inf` or `-abc` as unknown flags, and `allow_hyphen_values` would swallow
//! a trailing `--json` into the values. So, for every command that sets
//! `allow_negative_numbers`, [`protect_hyphen_values`] rewrites
//!
//! ```text
//! reach fk ur5 -.5 -inf 0 0 0 0 --json   →   reach fk --json -- ur5 -.5 -inf 0 0 0 0
//! ```
//!
//! moving the options (with their values) in front of a `--` and keeping every positional
//! argument in its order after it. The values then reach the joint-value parser, which
//! names the joint in its one-line error (`joint 2: expected a finite number, got "-inf"`).
//! Nothing changes when the command line already contains `--` or has no hyphen value.

use std::ffi::OsString;

/// Rewrites `args` (program name first) as described in the module docs, using `root` (the
/// clap command tree) to know the subcommands and which options take a value.
#[must_use]
pub fn protect_hyphen_values(root: &clap::Command, args: Vec<OsString>) -> Vec<OsString> {
    let mut root = root.clone();
    root.build();
    // Descend through the subcommand names at the front.
    let mut command = &root;
    let mut i = 1;
    while let Some(sub) = args.get(i).and_then(|a| a.to_str()).and_then(|name| command.find_subcommand(name)) {
        command = sub;
        i += 1;
    }
    let negative_numbers = command.is_allow_negative_numbers_set()
        || command.get_positionals().any(clap::Arg::is_allow_negative_numbers_set);
    if !negative_numbers || args[i..].iter().any(|a| a == "--") {
        return args;
    }
    let takes_value = |token: &str| -> Option<bool> {
        // Some(takes a value) for a known option, None for an unknown one.
        command.get_arguments().find_map(|arg| {
            let long = token.strip_prefix("--").is_some_and(|name| {
                arg.get_long() == Some(name) || arg.get_all_aliases().is_some_and(|a| a.contains(&name))
            });
            let short = token.len() == 2 && token.starts_with('-') && token[1..].chars().next() == arg.get_short();
            (long || short).then(|| arg.get_action().takes_values())
        })
    };
    let mut options = Vec::new();
    let mut positionals = Vec::new();
    let mut hyphen_value = false;
    let mut k = i;
    while k < args.len() {
        let token = args[k].to_string_lossy().into_owned();
        let is_option = token.starts_with("--") || takes_value(&token).is_some();
        if is_option && token.len() > 1 {
            options.push(args[k].clone());
            if !token.contains('=') && takes_value(&token) == Some(true) && k + 1 < args.len() {
                k += 1;
                options.push(args[k].clone());
            }
        } else {
            hyphen_value |= token.starts_with('-') && token.len() > 1;
            positionals.push(args[k].clone());
        }
        k += 1;
    }
    if !hyphen_value {
        return args;
    }
    let mut out: Vec<OsString> = args[..i].to_vec();
    out.extend(options);
    out.push("--".into());
    out.extend(positionals);
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    fn rewrite(line: &str) -> String {
        let args: Vec<OsString> = line.split(' ').map(OsString::from).collect();
        let out = protect_hyphen_values(&crate::cli::Cli::command(), args);
        out.iter().map(|a| a.to_string_lossy().into_owned()).collect::<Vec<_>>().join(" ")
    }

    #[test]
    fn moves_options_before_an_escape_when_values_start_with_a_hyphen() {
        assert_eq!(
            rewrite("reach fk ur5 -.5 -inf 0 --json --base b --tip=t"),
            "reach fk --json --base b --tip=t -- ur5 -.5 -inf 0"
        );
        assert_eq!(rewrite("reach jacobian --rad p -1 -h"), "reach jacobian --rad -h -- p -1");
    }

    #[test]
    fn leaves_other_command_lines_alone() {
        for line in [
            "reach fk ur5 0 1 2 --json",
            "reach fk ur5 -- -1 2",
            "reach robot show -x",
            "reach robots --json",
            "reach ik ur5 --xyz -0.3,0.2,0.5 --from -90,-45,0,0,0,0 --json",
            "reach --help",
        ] {
            assert_eq!(rewrite(line), line);
        }
    }
}
