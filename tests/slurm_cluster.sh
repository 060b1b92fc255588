# A real one-node Slurm cluster from Debian 12's packages (slurm-wlm, munge), without systemd.
# Source it, then `cluster_up DIR` and `cluster_down`; cluster_up exports SLURM_CONF, so sbatch,
# squeue, scontrol (and pcrt cluster) in this shell talk to this cluster only.
#
# Everything lives under DIR: munge key, socket, state, spool, logs. The daemons run in the
# foreground as background jobs of this shell; their PIDs are recorded in DIR/pids and cluster_down
# kills exactly those (never by name: other clusters may run on this machine), then keeps the list
# in DIR/pids.down. Ports come from PCRT_SLURMCTLD_PORT / PCRT_SLURMD_PORT, or are free ports
# picked by the kernel, so two clusters on one machine do not collide; DIR (the state directory)
# is the caller's.

cluster_log() { echo "slurm_cluster: $*" >&2; }

cluster_free_port() {
  /usr/bin/python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}

# Starts one daemon in the foreground as a background job and records its PID.
cluster_spawn() {
  local name=$1; shift
  "$@" </dev/null >"$CLUSTER_DIR/$name.out" 2>&1 &
  echo "$! $name" >>"$CLUSTER_DIR/pids"
}

cluster_write_conf() {
  local dir=$1 ctld_port=$2 d_port=$3 node
  # slurmd -C prints the node line and an UpTime line; only the first belongs in slurm.conf.
  node=$(slurmd -C | head -1)
  cat >"$dir/slurm.conf" <<EOF
ClusterName=pcrt
SlurmctldHost=$(hostname | cut -d. -f1)(127.0.0.1)
SlurmUser=root
SlurmdUser=root
SlurmctldPort=$ctld_port
SlurmdPort=$d_port
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
TmpFS=$dir/tmp
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/backfill
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
JobCompType=jobcomp/none
MailProg=/bin/true
ReturnToService=2
MinJobAge=600
$node NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=debug Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
}

# munged and its clients reach the socket through every directory above it: each needs o+x.
# Directories of the cluster get it; a parent outside that lacks it is reported, not changed.
cluster_open_path() {
  local top=$1 d
  d=$(realpath "$top")
  chmod 0711 "$d" "$d/munge"
  d=$(dirname "$d")
  while [ "$d" != / ]; do
    if [ "$(stat -c %A "$d" | cut -c10)" != x ] && [ "$(stat -c %A "$d" | cut -c10)" != t ]; then
      cluster_log "$d lacks o+x, which munged needs on every directory above its socket"
      return 1
    fi
    d=$(dirname "$d")
  done
}

cluster_start_munge() {
  local dir=$1
  mkdir -p "$dir/munge"
  dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 0400 "$dir/munge/munge.key"
  cluster_open_path "$dir" || return 1
  # --force: a throw-away key in a temporary directory need not pass the checks munged makes for
  # a production key (ownership and write permissions of every parent directory).
  cluster_spawn munged munged --foreground --force --socket="$dir/munge/munge.socket" \
    --key-file="$dir/munge/munge.key" --pid-file="$dir/munge/munged.pid" \
    --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/munged.seed"
  local i
  for i in $(seq 100); do
    [ -S "$dir/munge/munge.socket" ] && return 0
    sleep 0.1
  done
  cluster_log "munged did not create its socket:"; cat "$dir/munged.out" >&2
  return 1
}

cluster_wait_idle() {
  local i state
  for i in $(seq 300); do
    state=$(sinfo -h -N -o %T 2>/dev/null | head -1)
    [ "$state" = idle ] && return 0
    sleep 0.1
  done
  cluster_log "the node never became idle (state '$state'); slurmctld log:"
  tail -20 "$CLUSTER_DIR/slurmctld.log" >&2 || true
  tail -20 "$CLUSTER_DIR/slurmd.log" >&2 || true
  return 1
}

# cluster_up DIR: brings the cluster up in DIR (created), exports SLURM_CONF and CLUSTER_DIR.
cluster_up() {
  CLUSTER_DIR=$1
  mkdir -p "$CLUSTER_DIR"/{state,spool,tmp}
  : >"$CLUSTER_DIR/pids"
  local ctld_port=${PCRT_SLURMCTLD_PORT:-$(cluster_free_port)}
  local d_port=${PCRT_SLURMD_PORT:-$(cluster_free_port)}
  cluster_write_conf "$CLUSTER_DIR" "$ctld_port" "$d_port"
  export SLURM_CONF=$CLUSTER_DIR/slurm.conf CLUSTER_DIR
  cluster_start_munge "$CLUSTER_DIR" || return 1
  cluster_spawn slurmctld slurmctld -D -i -f "$SLURM_CONF"
  cluster_spawn slurmd slurmd -D -f "$SLURM_CONF"
  cluster_wait_idle
}

# Job steps run under slurmstepd, which outlives slurmd: cancel every job of this cluster while
# its daemons can still stop them.
cluster_cancel_jobs() {
  scancel --user="$(id -un)" 2>/dev/null || return 0
  for _ in $(seq 100); do
    [ -z "$(squeue -h -o %i 2>/dev/null)" ] && return 0
    sleep 0.1
  done
  cluster_log "jobs still listed after scancel"
}

# Anything still carrying this cluster's SLURM_CONF (a step whose slurmd died first) apart from
# this shell: found by PID in /proc, never by name.
cluster_kill_leftovers() {
  local env pid
  for env in /proc/[0-9]*/environ; do
    pid=${env#/proc/}; pid=${pid%/environ}
    [ "$pid" = $$ ] || [ "$pid" = "$BASHPID" ] && continue
    if grep -qzxF -- "SLURM_CONF=$CLUSTER_DIR/slurm.conf" "$env" 2>/dev/null; then
      kill -9 "$pid" 2>/dev/null && cluster_log "left-over process $pid killed" || true
    fi
  done
}

# Cancels the jobs, kills the recorded daemons (slurmd first) and waits for them.
cluster_down() {
  [ -n "${CLUSTER_DIR:-}" ] && [ -f "$CLUSTER_DIR/pids" ] || return 0
  cluster_cancel_jobs
  local pid name
  while read -r pid name; do
    kill "$pid" 2>/dev/null || true
  done < <(tac "$CLUSTER_DIR/pids")
  for _ in $(seq 50); do
    local alive=0
    while read -r pid name; do kill -0 "$pid" 2>/dev/null && alive=1; done <"$CLUSTER_DIR/pids"
    [ $alive = 0 ] && break
    sleep 0.1
  done
  while read -r pid name; do
    kill -9 "$pid" 2>/dev/null && cluster_log "$name ($pid) killed with SIGKILL" || true
  done <"$CLUSTER_DIR/pids"
  cluster_kill_leftovers
  # Kept for a check that nothing survived; a second cluster_down has nothing left to kill.
  mv "$CLUSTER_DIR/pids" "$CLUSTER_DIR/pids.down"
}
