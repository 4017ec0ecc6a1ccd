//! `pbdda`: thin binary over the library (see `pbdda::cli`).

fn main() -> miette::Result<()> {
    pbdda::cli::run_from_args()
}
