// Inclusive prefix sum of u32 in place, reduce-then-scan (gpu-notes.md: portable, no reliance
// on forward progress between workgroups). Host side: src/gpu/scan.rs, which records, for each
// level of the block hierarchy, `scan_block` from the finest level up, then `scan_add` from the
// coarsest down. CPU twin: a running sum.

@group(0) @binding(0) var<uniform> level: ScanLevel;
@group(0) @binding(1) var<storage, read_write> data: array<u32>;
// One entry per block of `data`: the block's total.
@group(0) @binding(2) var<storage, read_write> sums: array<u32>;

var<workgroup> partial: array<u32, WG>;

// Scan one block of `data` in place; the block's total to sums[block].
@compute @workgroup_size(WG)
fn scan_block(@builtin(workgroup_id) wid: vec3<u32>,
              @builtin(local_invocation_index) local: u32) {
    let base = wid.x * SCAN_BLOCK + local * SCAN_ITEMS;
    var run = 0u;
    for (var k = 0u; k < SCAN_ITEMS; k++) {
        let at = base + k;
        if (at < level.len) {
            run += data[at];
            data[at] = run;
        }
    }
    // Inclusive Hillis–Steele scan of the WG thread totals.
    partial[local] = run;
    workgroupBarrier();
    for (var stride = 1u; stride < WG; stride = stride << 1u) {
        var add = 0u;
        if (local >= stride) {
            add = partial[local - stride];
        }
        workgroupBarrier();
        partial[local] += add;
        workgroupBarrier();
    }
    let before = partial[local] - run;
    for (var k = 0u; k < SCAN_ITEMS; k++) {
        let at = base + k;
        if (at < level.len) {
            data[at] += before;
        }
    }
    if (local == WG - 1u) {
        sums[wid.x] = partial[local];
    }
}

// Add the (scanned) totals of the blocks before each block; block 0 has none.
@compute @workgroup_size(WG)
fn scan_add(@builtin(workgroup_id) wid: vec3<u32>,
            @builtin(local_invocation_index) local: u32) {
    if (wid.x == 0u) { return; }
    let add = sums[wid.x - 1u];
    let base = wid.x * SCAN_BLOCK + local * SCAN_ITEMS;
    for (var k = 0u; k < SCAN_ITEMS; k++) {
        let at = base + k;
        if (at < level.len) {
            data[at] += add;
        }
    }
}
