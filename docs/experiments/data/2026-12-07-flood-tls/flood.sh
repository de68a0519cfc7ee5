#!/usr/bin/env bash
# One flood round against a plain server, then one against TLS + tokens.
set -u
cd /work/main
D=/tmp/flood_tls; rm -rf $D; mkdir -p $D; chmod 700 $D
(umask 077; openssl req -x509 -newkey rsa:2048 -nodes -days 2 -subj /CN=localhost \
  -addext "subjectAltName=DNS:localhost,IP:127.0.0.1" -keyout $D/key.pem -out $D/cert.pem 2>/dev/null
 printf 'plan flood-probe-token-0123456789abcdef probe\n' > $D/tokens
 printf 'flood-probe-token-0123456789abcdef\n' > $D/probe.token)
for mode in plain tls; do
  if [[ $mode == tls ]]; then
    sargs=(--auth-tokens $D/tokens --tls-cert $D/cert.pem --tls-key $D/key.pem)
    aargs=(--ca-file $D/cert.pem --token-file $D/probe.token)
  else sargs=(); aargs=(); fi
  build/bin/hfts-server --db build/databases --port 7461 --quiet "${sargs[@]}" > $D/server_$mode.out 2>&1 &
  pid=$!
  for _ in $(seq 300); do grep -q listening $D/server_$mode.out && break; sleep 0.1; done
  /usr/bin/python3 tests/cli/server_attack.py --port 7461 --pid $pid --connections 200 --mib 15 "${aargs[@]}" > $D/attack_$mode.json 2>&1
  kill $pid; wait $pid
done
echo done > $D/done
