"""Speed reference for eitbench's trainer (docs/gpu.md): the paper's MLP->CNN (as eitbench's `paper` and `small` presets define it) trained by plain PyTorch.
Measures training throughput (samples/s) and batch-1 inference latency on whatever device is present.
Usage: python3 torch_ref.py [cpu|cuda] [seconds per case] [eager|tuned|compiled] [SIZE:BATCH, e.g. paper:512: that case alone]"""
import sys, time, torch, torch.nn as nn

def model(size):
    hidden, C, dec, p = ([512, 1024], 64, [32, 16, 8], 0.2) if size == "paper" else ([256], 32, [16, 8, 4], 0.1)
    enc, w = [], 104
    for h in hidden:
        enc += [nn.Linear(w, h), nn.BatchNorm1d(h), nn.ReLU(), nn.Dropout(p)]; w = h
    enc += [nn.Linear(w, C * 64), nn.BatchNorm1d(C * 64), nn.ReLU()]
    layers, c = [], C
    for o in dec:
        layers += [nn.Upsample(scale_factor=2, mode="nearest"), nn.Conv2d(c, o, 3, padding=1, bias=False), nn.BatchNorm2d(o), nn.ReLU()]; c = o
    layers += [nn.Conv2d(c, 1, 3, padding=1)]
    class Net(nn.Module):
        def __init__(s):
            super().__init__(); s.enc = nn.Sequential(*enc); s.dec = nn.Sequential(*layers)
        def forward(s, x):
            return s.dec(s.enc(x).view(-1, C, 8, 8)).view(-1, 4096)
    return Net()

def main():
    dev = sys.argv[1] if len(sys.argv) > 1 else ("cuda" if torch.cuda.is_available() else "cpu")
    secs = float(sys.argv[2]) if len(sys.argv) > 2 else 5
    mode = sys.argv[3] if len(sys.argv) > 3 else "eager"   # eager | tuned (cudnn benchmark, TF32) | compiled (torch.compile, CUDA graphs)
    if mode != "eager":
        torch.backends.cudnn.benchmark = True
        torch.backends.cuda.matmul.allow_tf32 = True; torch.backends.cudnn.allow_tf32 = True
    print("torch", torch.__version__, "mode", mode, "device", dev, "threads", torch.get_num_threads(),
          torch.cuda.get_device_name() if dev == "cuda" else "")
    def sync():
        if dev == "cuda": torch.cuda.synchronize()
    N = 20000
    X = torch.randn(N, 104, device=dev); Y = torch.rand(N, 4096, device=dev)
    only = sys.argv[4].split(":") if len(sys.argv) > 4 else None
    for size in ([only[0]] if only else ["small", "paper"]):
        for batch in ([int(only[1])] if only else [128, 512]):
            for amp in ([False, True] if dev == "cuda" else [False]):
                torch.manual_seed(0); m = model(size).to(dev); opt = torch.optim.Adam(m.parameters(), 1e-3)
                fwd = torch.compile(m, mode="reduce-overhead") if mode == "compiled" else m
                nparam = sum(p.numel() for p in m.parameters())
                def step(i):
                    idx = torch.randint(0, N, (batch,), device=dev)
                    with torch.autocast(device_type=dev, dtype=torch.bfloat16, enabled=amp):
                        loss = nn.functional.mse_loss(fwd(X[idx]).float(), Y[idx])
                    opt.zero_grad(set_to_none=True); loss.backward(); opt.step()
                for i in range(5): step(i)
                sync(); t0 = time.time(); n = 0
                while time.time() - t0 < secs:
                    for _ in range(10): step(n); n += 1
                    sync()
                dt = time.time() - t0
                print(f"train {size:5s} params {nparam/1e6:.2f}M batch {batch:4d} {'bf16' if amp else 'fp32'}: {n*batch/dt:10.0f} samples/s")
        m.eval()
        with torch.no_grad():
            x1 = X[:1]
            for _ in range(20): m(x1)
            sync(); t0 = time.time(); k = 0
            while time.time() - t0 < 2:
                m(x1); k += 1
            sync(); print(f"infer {size} batch 1: {(time.time()-t0)/k*1e3:.3f} ms/frame")

if __name__ == "__main__":
    main()
