#[allow(dead_code)]
mod plant;

fn main() { println!("host-sim: under construction"); }
