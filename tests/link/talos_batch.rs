//! Requests queued together reach the operator in one write: the ICD dialect's stop set (three
//! frames) is one segment, so its polar STOP does not wait for a second system call, and each
//! of its requests is still answered by its own reply.

use crate::common::{ok_reply, reply_bytes, stop_set, wire};

use std::io;
use std::pin::Pin;
use std::sync::Arc;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::task::{Context, Poll};

use futures::StreamExt;
use tokio::io::{AsyncRead, AsyncWrite, AsyncWriteExt, DuplexStream, ReadBuf};
use tokio_util::codec::FramedRead;

use armjog::link::{Dialect, TalosConfig, TalosLink};
use armjog::talos::frame::Decoded;
use armjog::talos::stop::stop_requests;
use armjog::talos::{Checksum, FrameCodec, TalosFrame};

/// The link's end of an in-memory stream, counting the writes that moved bytes.
struct CountedWrites {
    inner: DuplexStream,
    writes: Arc<AtomicUsize>,
}

impl AsyncRead for CountedWrites {
    fn poll_read(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &mut ReadBuf<'_>,
    ) -> Poll<io::Result<()>> {
        Pin::new(&mut self.inner).poll_read(cx, buf)
    }
}

impl AsyncWrite for CountedWrites {
    fn poll_write(
        mut self: Pin<&mut Self>,
        cx: &mut Context<'_>,
        buf: &[u8],
    ) -> Poll<io::Result<usize>> {
        let written = Pin::new(&mut self.inner).poll_write(cx, buf);
        if let Poll::Ready(Ok(n)) = &written
            && *n > 0
        {
            self.writes.fetch_add(1, Ordering::SeqCst);
        }
        written
    }

    fn poll_flush(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.inner).poll_flush(cx)
    }

    fn poll_shutdown(mut self: Pin<&mut Self>, cx: &mut Context<'_>) -> Poll<io::Result<()>> {
        Pin::new(&mut self.inner).poll_shutdown(cx)
    }
}

#[tokio::test]
async fn the_stop_set_queued_at_once_goes_out_in_one_write_and_each_stop_is_answered() {
    let (ours, theirs) = tokio::io::duplex(4096);
    let writes = Arc::new(AtomicUsize::new(0));
    let link_end = CountedWrites {
        inner: ours,
        writes: writes.clone(),
    };
    let (link, _events) = TalosLink::over(link_end, TalosConfig::new("duplex"));
    // Queued before the link's task runs: it finds all three waiting.
    let pending: Vec<_> = stop_requests(Dialect::Icd)
        .into_iter()
        .map(|stop| link.submit(stop).expect("queued"))
        .collect();

    let (read, mut replies) = tokio::io::split(theirs);
    let mut frames = FramedRead::new(read, FrameCodec::new(Checksum::Crc16));
    let mut got: Vec<TalosFrame> = Vec::new();
    while got.len() < 3 {
        match frames.next().await {
            Some(Ok(Decoded::TalosFrame(frame))) => got.push(frame),
            other => panic!("expected a request frame, got {other:?}"),
        }
    }
    assert_eq!(wire(&got), stop_set(Dialect::Icd));
    assert_eq!(
        writes.load(Ordering::SeqCst),
        1,
        "the three frames in one write"
    );

    // Answered out of order: each reply still finds its own request.
    for frame in got.iter().rev() {
        let bytes = reply_bytes(&ok_reply(frame), frame.id, Checksum::Crc16);
        replies.write_all(&bytes).await.expect("reply");
    }
    for (stop, answer) in stop_requests(Dialect::Icd).iter().zip(pending) {
        let exchange = answer.wait().await.expect("answered");
        assert_eq!(exchange.request, *stop);
    }
}
