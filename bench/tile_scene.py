"""Tile a square float32 .npy scene K x K times into one larger .npy (pure Python, no numpy):
the large scenes `detect_scene.sh` times `wakelab detect` on."""
import struct, sys
src, k, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
b=open(src,'rb').read(); hl=struct.unpack('<H',b[8:10])[0]; h=b[10:10+hl].decode(); d=b[10+hl:]
assert "'<f4'" in h, h
n=int(h.split('(')[1].split(',')[0])
rows=[d[r*n*4:(r+1)*n*4] for r in range(n)]
N=n*k
header="{'descr': '<f4', 'fortran_order': False, 'shape': (%d, %d), }" % (N, N)
while (10+len(header)+1)%64: header+=' '
header+='\n'
with open(out,'wb') as f:
    f.write(b'\x93NUMPY\x01\x00'+struct.pack('<H',len(header))+header.encode())
    for i in range(k):
        for r in range(n): f.write(rows[r]*k)
