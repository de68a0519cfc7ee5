#!/usr/bin/env bash
# Starts N hfts-server instances and HAProxy in front of them, all on
# loopback, and runs until Ctrl-C (or SIGTERM), which stops them all.
#
#   scripts/scale_out.sh N [--port 7450] [--base-port 7451] [--workers 1]
#                          [--db build/databases] [--dir RUN_DIR]
#                          [--auth-tokens FILE --check-token FILE] [--tls]
#                          [--bin build/bin] [-- more hfts-server options]
#
# Clients talk to the balancer on --port as to one server. Instance i
# listens on base-port + i - 1 (--base-port 0: ports the system picks).
# Each instance plans with --workers threads; the programs come from --bin.
# RUN_DIR (default: a new folder under /tmp) holds the HAProxy config, its
# stats socket and every log. The lines "instance I pid PID port PORT",
# "haproxy pid PID" and finally "balancer listening on 127.0.0.1:PORT" go
# to standard output.
# The config is deploy/haproxy/hfts.cfg with one server line per instance.
# With --auth-tokens every instance requires tokens (docs/security.md); the
# health check and the readiness call use the plan token in the first line
# of --check-token's file. With --tls HAProxy speaks TLS to the clients
# with a self-signed certificate for localhost and 127.0.0.1 made in
# RUN_DIR (cert.pem: give it to the clients as their CA file) and plain TCP
# to the instances.
set -euo pipefail
root=$(cd "$(dirname "$0")/.." && pwd)

usage() { sed -n '2,24p' "$0" | sed 's/^# \{0,1\}//'; exit 2; }
fail() { echo "scale_out: $*" >&2; exit 1; }

[[ $# -ge 1 && "$1" =~ ^[0-9]+$ && "$1" -ge 1 ]] || usage
instances=$1
shift
port=7450 base_port=7451 workers=1 db=$root/build/databases run_dir="" bin=$root/build/bin
tokens="" check_token="" tls=no
server_args=()
while [[ $# -gt 0 ]]; do
  case "$1" in
    --port) port=$2; shift 2 ;;
    --base-port) base_port=$2; shift 2 ;;
    --workers) workers=$2; shift 2 ;;
    --db) db=$2; shift 2 ;;
    --dir) run_dir=$2; shift 2 ;;
    --bin) bin=$2; shift 2 ;;
    --auth-tokens) tokens=$2; shift 2 ;;
    --check-token) check_token=$2; shift 2 ;;
    --tls) tls=yes; shift ;;
    --) shift; server_args=("$@"); break ;;
    *) usage ;;
  esac
done
for number in "$port" "$base_port" "$workers"; do
  [[ "$number" =~ ^[0-9]+$ ]] || fail "not a number: '$number'"
done

[[ -z $tokens || -n $check_token ]] || fail "--auth-tokens needs --check-token FILE (a plan token)"
client_args=() token_args=()
if [[ -n $tokens ]]; then
  [[ -r $check_token ]] || fail "cannot read the check token file '$check_token'"
  check_token=$(realpath "$check_token")
  token_args=(--auth-tokens "$(realpath "$tokens")")
  client_args=(--token-file "$check_token")
  HFTS_CHECK_TOKEN=$(head -n 1 "$check_token" | tr -d '[:space:]')
  export HFTS_CHECK_TOKEN
fi

server=$bin/hfts-server client=$bin/hfts-client
[[ -x $server && -x $client ]] || fail "$server or $client is missing: run scripts/build.sh first"
[[ -d $db ]] || fail "no database folder '$db': run scripts/demo.sh (or hfts-preprocess) first"
command -v haproxy >/dev/null || fail "haproxy is missing: run scripts/setup.sh"
run_dir=${run_dir:-$(mktemp -d /tmp/hfts-scale-out.XXXXXX)}
mkdir -p "$run_dir"
# The servers find the robot and the scenes from the repository's root.
db=$(realpath "$db") run_dir=$(realpath "$run_dir") server=$(realpath "$server")
client=$(realpath "$client")
cd "$root"

pids=()
stop_all() {
  trap - INT TERM EXIT
  [[ ${#pids[@]} -gt 0 ]] && kill "${pids[@]}" 2>/dev/null || true
  wait 2>/dev/null || true
}
trap stop_all EXIT
trap 'exit 0' INT TERM

# Waits until FILE has a line matching PATTERN (or the process PID ends);
# prints the line.
wait_for_line() {
  local file=$1 pattern=$2 pid=$3 line
  for _ in $(seq 600); do
    line=$(grep -m1 -E "$pattern" "$file" 2>/dev/null || true)
    [[ -n $line ]] && { echo "$line"; return 0; }
    kill -0 "$pid" 2>/dev/null || return 1
    sleep 0.1
  done
  return 1
}

cfg=$run_dir/haproxy.cfg
cp "$root/deploy/haproxy/hfts.cfg" "$cfg"
for i in $(seq "$instances"); do
  instance_port=$((base_port == 0 ? 0 : base_port + i - 1))
  "$server" --db "$db" --bind 127.0.0.1 --port "$instance_port" --workers "$workers" \
    "${token_args[@]}" "${server_args[@]}" >"$run_dir/server$i.out" 2>"$run_dir/server$i.log" &
  pids+=($!)
  line=$(wait_for_line "$run_dir/server$i.out" "listening on" $!) ||
    fail "instance $i did not start: $(tail -n 3 "$run_dir/server$i.log")"
  instance_port=${line##*:}
  echo "instance $i pid ${pids[-1]} port $instance_port"
  echo "    server hfts$i 127.0.0.1:$instance_port check" >>"$cfg"
done

export HFTS_BIND=127.0.0.1 HFTS_PORT=$port HFTS_STATS_SOCKET=$run_dir/haproxy.sock
export HFTS_CHECK_TOKEN=${HFTS_CHECK_TOKEN:-}
if [[ $tls == yes ]]; then
  command -v openssl >/dev/null || fail "openssl is missing: run scripts/setup.sh"
  (umask 077 && openssl req -x509 -newkey rsa:2048 -nodes -days 30 -subj /CN=localhost \
    -addext "subjectAltName=DNS:localhost,IP:127.0.0.1" -keyout "$run_dir/key.pem" \
    -out "$run_dir/cert.pem" 2>"$run_dir/openssl.log" &&
    cat "$run_dir/cert.pem" "$run_dir/key.pem" >"$run_dir/haproxy.pem") ||
    fail "openssl failed: $run_dir/openssl.log"
  export HFTS_TLS_PEM=$run_dir/haproxy.pem
  client_args+=(--ca-file "$run_dir/cert.pem")
fi
haproxy -c -q -f "$cfg" || fail "haproxy rejected $cfg"
haproxy -db -f "$cfg" 2>"$run_dir/haproxy.log" &
pids+=($!)
echo "haproxy pid ${pids[-1]}"

# Ready when a call through the balancer is answered.
for _ in $(seq 100); do
  if "$client" --port "$port" --retries 0 "${client_args[@]}" info >/dev/null 2>&1; then
    tls_note=""
    [[ $tls == yes ]] && tls_note=", TLS with the CA $run_dir/cert.pem"
    echo "balancer listening on 127.0.0.1:$port ($instances instances$tls_note; logs in $run_dir)"
    # Until Ctrl-C, or until HAProxy ends.
    wait "${pids[-1]}" || true
    exit 0
  fi
  kill -0 "${pids[-1]}" 2>/dev/null || fail "haproxy ended: $(tail -n 3 "$run_dir/haproxy.log")"
  sleep 0.1
done
fail "the balancer on port $port does not answer (logs in $run_dir)"
