//! Writing one step's results, as `pbdda run` does on every written step: the four CSV files
//! (`CsvWriter::write_step`: rows formatted on both cores from 2,048 rows on, laid out and
//! written in one write per file) and the ParaView `.vtu` (`VtkWriter::write_step`), for the
//! 1,000- and 10,000-disk bench piles after 20 steps. Each sample writes into files created
//! afresh (outside the timing), so the files do not grow from sample to sample. The bytes of
//! one step are printed once per pile.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use pbdda::generate::DiskPile;
use pbdda::output::csv::CsvWriter;
use pbdda::output::vtk::VtkWriter;
use pbdda::world::{StepRecord, World};
use std::path::{Path, PathBuf};

fn pile(columns: usize, rows: usize) -> (World, StepRecord) {
    let mut world = World::new(DiskPile::benchmark(columns, rows).model());
    let mut rec = world.step().expect("pile step");
    for _ in 1..20 {
        rec = world.step().expect("pile step");
    }
    (world, rec)
}

fn size(dir: &Path) -> u64 {
    std::fs::read_dir(dir).map_or(0, |d| d.flatten().filter_map(|e| e.metadata().ok()).map(|m| m.len()).sum())
}

fn bench(c: &mut Criterion) {
    let root: PathBuf = std::env::temp_dir().join(format!("pbdda-bench-output-{}", std::process::id()));
    for (columns, rows) in [(40, 25), (100, 100)] {
        let (world, rec) = pile(columns, rows);
        let n = columns * rows;
        let dir = root.join(n.to_string());
        let csv = || CsvWriter::create(&dir, 1, rec.step, true).expect("csv writer");
        let vtk = || VtkWriter::create(&dir, &world).expect("vtk writer");
        csv().write_step(&world, &rec).expect("csv step");
        vtk().write_step(&world, &rec).expect("vtk step");
        eprintln!(
            "{n} disks, {} contacts: CSVs {} bytes, vtk/ {} bytes a step",
            rec.contacts.len(),
            size(&dir),
            size(&dir.join("vtk"))
        );
        let mut group = c.benchmark_group("output");
        if n > 1000 {
            group.sample_size(10);
        }
        group.bench_function(format!("csv_step/{n}"), |b| {
            b.iter_batched(
                csv,
                |mut w| w.write_step(&world, &rec).expect("csv step"),
                BatchSize::PerIteration,
            )
        });
        group.bench_function(format!("vtk_step/{n}"), |b| {
            b.iter_batched(
                vtk,
                |mut w| w.write_step(&world, &rec).expect("vtk step"),
                BatchSize::PerIteration,
            )
        });
        group.finish();
    }
    let _ = std::fs::remove_dir_all(&root);
}

criterion_group!(benches, bench);
criterion_main!(benches);
